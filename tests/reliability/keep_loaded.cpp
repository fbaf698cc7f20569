// LD_PRELOAD for leak checks (tests/reliability/view_leak_check.sh): dlclose does nothing, so
// the libraries that the Vulkan loader (drivers, layers) and GLFW (libX11 and its kin) open
// at run time stay loaded until the process ends. LeakSanitizer then still finds their
// globals (what they keep for the process's life is reachable, not leaked) and can name them
// in a stack, which tests/reliability/lsan.supp needs to match a library. Newer Vulkan
// loaders do the same with VK_LOADER_DISABLE_DYNAMIC_LIBRARY_UNLOADING=1; Debian 12's lacks it.
// Built without sanitizers: it is preloaded into the sanitized `skygraph` only.
extern "C" int dlclose(void*) { return 0; }
