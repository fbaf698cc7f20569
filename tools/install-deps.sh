#!/usr/bin/env bash
# Installs skygraph's build and test dependencies: Debian 12 packages only.
set -euo pipefail
packages=(
  cmake ninja-build g++ pkg-config
  nlohmann-json3-dev libspdlog-dev libfmt-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libvulkan-dev vulkan-validationlayers mesa-vulkan-drivers vulkan-tools
  glslang-dev glslang-tools spirv-tools libglm-dev
  libstb-dev libopenexr-dev blender-data
  graphviz python3-jsonschema libdtl-dev
  libglfw3-dev libimgui-dev  # `skygraph view`'s window (GLFW)
  libtinygltf-dev assimp-testmodels  # glTF scene objects; the test models (tests/scene, tests/passes)
  xvfb xauth x11-apps xdotool imagemagick  # tests/present: a virtual X server, window control, screenshots
  liblcms2-dev python3-matplotlib  # bench/study: CIEDE2000, the Pareto plot (docs/tradeoffs.md)
  libopencolorio-dev  # the reference ACES RRT + ODT (bench/aces_reference.hpp, math_tests, study)
  clang-14 libclang-rt-14-dev llvm-14  # libFuzzer, ASan/UBSan runtimes, llvm-symbolizer (docs/reliability.md)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# ktx-parse: the independent KTX2 reader that tests/ibl runs under node to check
# `skygraph cubemap`'s files. From the npm registry into build-deps/node (ignored by git).
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends nodejs npm
fi
if [ ! -f "$root/build-deps/node/node_modules/ktx-parse/package.json" ]; then
  npm install --prefix "$root/build-deps/node" --no-audit --no-fund --loglevel=error ktx-parse@2.0.0
fi
