#!/usr/bin/env bash
# Packs what skygraph's build needs on a GPU machine that has a compiler, cmake and a Vulkan
# driver but no packages of ours and no network (the H100 machine of docs/performance.md):
# the headers, static and shared libraries and CMake package files of the Debian 12 packages
# that tools/install-deps.sh installs, plus the Vulkan loader and the GL vendor-neutral
# dispatch libraries that NVIDIA's Vulkan driver loads. Copied from this machine's installed
# packages (dpkg -L), so run tools/install-deps.sh first.
#
# With --source [PATH...], also .devbundle/source.tar.gz: `git archive` of HEAD or $BASE (with the
# working-tree versions of PATHs laid over it) and .devbundle/SOURCE_COMMIT, so the GPU
# machine builds a known snapshot rather than a working tree that other work is editing.
#
# Output: .devbundle/layer.tar.xz (the validation layer), .devbundle/deps.tar.xz (a usr/ tree, extracted on the GPU machine by
# tools/device/run-gpu-bench.sh; never into /, where it could break that system) and
# .devbundle/MANIFEST (package versions). .devbundle/ is listed in .git/info/exclude and
# travels with `carry: [".devbundle"]`.
set -euo pipefail
cd "$(git rev-parse --show-toplevel)"

# package: what it contributes (headers/cmake files, or the .so/.a the build links).
packages=(
  nlohmann-json3-dev libcli11-dev libglm-dev libstb-dev libstb0
  libspdlog-dev libspdlog1.10 libfmt-dev libfmt9
  libbenchmark-dev libbenchmark1debian
  libvulkan-dev libvulkan1
  glslang-dev spirv-tools
  libopenexr-dev libopenexr-3-1-30 libimath-dev libimath-3-1-29
  zlib1g-dev zlib1g
  libdtl-dev liblcms2-dev liblcms2-2
  libopencolorio-dev libopencolorio2.1 libpystring0 libyaml-cpp0.7
  libglvnd0 libglx0 libegl1 libgl1 libopengl0
  # `skygraph view`'s GLFW (configure needs its CMake files; linking `skygraph` needs libX11
  # and what it loads) and Dear ImGui (the ImGuiPass, bench/imgui_bench)
  libglfw3-dev libglfw3 libx11-6 libxcb1 libxau6 libxdmcp6 libbsd0 libmd0
  libimgui-dev
  # glTF scene objects (framework/scene)
  libtinygltf-dev libtinygltf2d
)
# install-deps.sh packages the GPU machine does not need from us: it has its own toolchain,
# runs no tests there (GoogleTest, validation layers, lavapipe, vulkaninfo, schema checks,
# graphviz, the clang-14 fuzzing and sanitizer stages, the X server of tests/present: it has no display) and renders no scene with blender-data's HDRIs (the bench uses scenes/default.json).
# glslang-tools contributes two files below. Any other package of install-deps.sh missing from both lists fails the bundle,
# so a new build dependency cannot be forgotten here.
not_needed=(cmake ninja-build g++ pkg-config libgtest-dev libgmock-dev vulkan-validationlayers
  mesa-vulkan-drivers vulkan-tools glslang-tools blender-data assimp-testmodels graphviz python3-jsonschema
  clang-14 libclang-rt-14-dev llvm-14 python3-matplotlib
  xvfb xauth x11-apps xdotool imagemagick)  # tests/present's X server and window tools

# Not needed to build or run: documentation, programs, Vulkan's C++ headers and XML registry,
# the SPIR-V tools' shared library (glslang links the static ones).
skip='^/usr/share/(doc|man|lintian|bug|vulkan/registry|pkgconfig)/|^/usr/bin/|^/usr/include/vulkan/.*\.(hpp|cppm)$|/libSPIRV-Tools-shared\.so|/libSPIRV-Tools-(diff|lint|reduce)\.a$|^/usr/share/(glm|nlohmann)/.*\.(md|txt)$'

# Data the measured scenes read: scenes/studio.json's HDRI (blender-data), as .devbundle/data/,
# and the glTF models of the reference scenes (assimp-testmodels), as .devbundle/data/gltf/.
data_files=(/usr/share/blender/datafiles/studiolights/world/studio.exr)
gltf_dirs=(BoxTextured-glTF-Binary ClearCoat-glTF 2CylinderEngine-glTF-Binary)

# Files that other packages' CMake files check for at configure time (glslang-targets.cmake
# imports glslang::glslangValidator and glslang::spirv-remap from glslang-tools).
extra_files=(/usr/bin/glslangValidator /usr/bin/spirv-remap)

out=.devbundle
deps_list=$(sed -n '/^packages=(/,/^)/p' tools/install-deps.sh | sed '1d;$d;s/#.*//' | tr -s ' \n' '\n' | sed '/^$/d')
for p in $deps_list; do
  case " ${packages[*]} ${not_needed[*]} " in *" $p "*) ;; *)
    echo "bundle.sh: tools/install-deps.sh installs $p; add it to packages or not_needed here" >&2; exit 1 ;;
  esac
done
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$out"
# The repository's exclude file (in a linked worktree, .git is a file: ask git for the path).
exclude=$(git rev-parse --git-path info/exclude)
grep -qx '/.devbundle/' "$exclude" 2>/dev/null || { mkdir -p "$(dirname "$exclude")"; echo '/.devbundle/' >> "$exclude"; }

manifest() {
  for p in "${packages[@]}"; do
    version=$(dpkg-query -W -f='${Version}' "$p" 2>/dev/null) || {
      echo "bundle.sh: package $p is not installed (run tools/install-deps.sh)" >&2; return 1; }
    echo "$p $version"
  done
  for f in "${extra_files[@]}"; do
    p=$(dpkg -S "$f" | cut -d: -f1)
    echo "$p $(dpkg-query -W -f='${Version}' "$p") ($f)"
  done
}
manifest > "$stage/MANIFEST"

# Re-pack only when the packages (or this script's lists) changed since the last bundle.
if [ -f "$out/deps.tar.xz" ] && cmp -s "$stage/MANIFEST" "$out/MANIFEST" && [ "$out/deps.tar.xz" -nt "$0" ]; then
  echo "bundle.sh: $out/deps.tar.xz is up to date"
else
  for p in "${packages[@]}"; do
    dpkg -L "$p" | grep -E '^/(usr|lib)/' | grep -Ev "$skip" | while read -r f; do
      # /lib is /usr/lib on merged-/usr systems: keep everything under usr/.
      dest="$stage/root/usr/${f#/usr/}"
      [ "${f#/lib/}" != "$f" ] && dest="$stage/root/usr/lib/${f#/lib/}"
      if [ -L "$f" ] || [ -f "$f" ]; then mkdir -p "$(dirname "$dest")"; cp -a "$f" "$dest"; fi
    done
  done
  for f in "${extra_files[@]}"; do
    mkdir -p "$stage/root$(dirname "$f")"; cp -aL "$f" "$stage/root$f"
  done
  # Debian's zlib1g-dev links libz.so to /lib/...; repoint absolute links inside the tree.
  find "$stage/root" -type l | while read -r l; do
    t=$(readlink "$l")
    case "$t" in /*) ln -sf "$(basename "$t")" "$l" ;; esac
  done
  tar -C "$stage/root" -cJf "$out/deps.tar.xz.tmp" usr
  mv "$out/deps.tar.xz.tmp" "$out/deps.tar.xz"
  cp "$stage/MANIFEST" "$out/MANIFEST"
  echo "bundle.sh: $(du -h "$out/deps.tar.xz" | cut -f1) in $out/deps.tar.xz ($(du -sh "$stage/root" | cut -f1) unpacked), $(wc -l < "$out/MANIFEST") packages"
fi

mkdir -p "$out/data"
for f in "${data_files[@]}"; do cp "$f" "$out/data/"; done
mkdir -p "$out/data/gltf"
for d in "${gltf_dirs[@]}"; do cp -r "/usr/share/assimp/models/glTF2/$d" "$out/data/gltf/"; done

# Debian's validation layer (vulkan-validationlayers), for runs under validation there:
# .devbundle/layer.tar.xz holds its library and manifest; run-gpu-bench.sh points
# VK_LAYER_PATH at them.
layer_files=(/usr/lib/x86_64-linux-gnu/libVkLayer_khronos_validation.so
             /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json)
if [ ! -f "$out/layer.tar.xz" ] || [ "${layer_files[0]}" -nt "$out/layer.tar.xz" ]; then
  mkdir -p "$stage/layer"
  cp "${layer_files[@]}" "$stage/layer/"
  tar -C "$stage/layer" -cJf "$out/layer.tar.xz" .
fi

# --source [PATH...]: HEAD (or the commit in $BASE, e.g. the last one that builds), with the
# working-tree versions of PATHs (your own uncommitted files) laid over it through a
# temporary index; the checkout and its index are untouched.
if [ "${1:-}" = "--source" ]; then
  shift
  base=$(git rev-parse "${BASE:-HEAD}")
  tree=$base
  if [ $# -gt 0 ]; then
    export GIT_INDEX_FILE="$stage/index"
    git read-tree "$base"
    git add -- "$@"
    tree=$(git write-tree)
    unset GIT_INDEX_FILE
  fi
  git archive --format=tar.gz --prefix=src/ -o "$out/source.tar.gz.tmp" "$tree"
  mv "$out/source.tar.gz.tmp" "$out/source.tar.gz"
  { echo "$base"; [ $# -gt 0 ] && echo "plus the working tree's: $*"; } > "$out/SOURCE_COMMIT"
  echo "bundle.sh: source of $(head -1 "$out/SOURCE_COMMIT") in $out/source.tar.gz${*:+ (plus $*)}"
else
  rm -f "$out/source.tar.gz" "$out/SOURCE_COMMIT"
fi
