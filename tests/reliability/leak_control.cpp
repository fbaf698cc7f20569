// The negative control of the leak check (tests/reliability/view_leak_check.sh): a program of
// skygraph code that makes a device with validation on lavapipe, as `skygraph view` does, so
// that the same loader, layer and driver are loaded, under the same suppressions and
// LD_PRELOAD. `clean` leaks nothing and must pass; `leak-object` leaks one allocation of its
// own and `leak-device` a whole Device (the loader's and driver's allocations hang off it):
// LeakSanitizer must report both, from this file's frames.
#include <skygraph/device.hpp>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace {

std::vector<int>* volatile sink = nullptr;

[[gnu::noinline]] void leakObject() {
    sink = new std::vector<int>(1000, 7);
    sink = nullptr;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode != "clean" && mode != "leak-object" && mode != "leak-device") {
        std::fprintf(stderr, "usage: leak_control clean|leak-object|leak-device\n");
        return 2;
    }
    skygraph::DeviceOptions o;
    o.device = "llvmpipe";
    o.validation = true;
    auto device = skygraph::Device::create(o);
    std::printf("leak_control %s: device '%s', %llu validation message(s)\n", mode.c_str(), device->name().c_str(),
                static_cast<unsigned long long>(device->messageCount()));
    if (mode == "leak-object") leakObject();
    if (mode == "leak-device") (void)device.release();
    return 0;
}
