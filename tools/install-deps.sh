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
