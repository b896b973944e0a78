#!/usr/bin/env bash
# Installs the Debian packages Dermis needs (if missing) and builds it in Release into build/.
# Usage: bash scripts/setup.sh [extra cmake arguments]
set -euo pipefail
cd "$(dirname "$0")/.."

# The GPU evaluation (docs/gpu.md): the Vulkan loader and headers, glslc for the shaders, Mesa's
# Vulkan drivers (lavapipe runs the shaders on the CPU where there is no GPU) and the Khronos
# validation layer the tests run under.
packages=(build-essential cmake libeigen3-dev libglm-dev catch2 libcli11-dev libmeshoptimizer-dev
          nlohmann-json3-dev libtinygltf-dev libassimp-dev libdraco-dev pkg-config libosd-dev
          libstb-dev liblemon-dev libvulkan-dev glslc mesa-vulkan-drivers vulkan-validationlayers
          clang-14 g++-aarch64-linux-gnu qemu-user file)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

build_dir="${DERMIS_BUILD_DIR:-build}"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE="${DERMIS_BUILD_TYPE:-Release}" "$@" >/dev/null
cmake --build "$build_dir" -j"$(nproc)"
