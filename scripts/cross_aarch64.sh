#!/usr/bin/env bash
# The runtime for 64-bit Arm (issue 17): a runtime-only cross build with Debian's
# g++-aarch64-linux-gnu (cmake/toolchains/aarch64-linux-gnu.cmake), its tests (deform, asset,
# dsurf, runtime, no allocation) run under qemu-aarch64 on the fixture files of a full build.
#   bash scripts/cross_aarch64.sh [FIXTURE_DIR] [BUILD_DIR]
# FIXTURE_DIR defaults to build/tests/fixtures (cmake --build build --target
# dermis_test_fixture_files writes them); BUILD_DIR to build-aarch64. Needs the Debian packages
# g++-aarch64-linux-gnu and qemu-user (scripts/setup.sh). Exit status: ctest's.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
fixtures=$(realpath -m "${1:-$root/build/tests/fixtures}")
out=$(realpath -m "${2:-$root/build-aarch64}")
jobs=${DERMIS_JOBS:-2}
for tool in aarch64-linux-gnu-g++ qemu-aarch64; do
  command -v "$tool" > /dev/null || {
    echo "cross_aarch64.sh: $tool is missing (apt-get install g++-aarch64-linux-gnu qemu-user)" >&2
    exit 2
  }
done
if [ ! -f "$fixtures/cylinders.dsurf" ]; then
  echo "cross_aarch64.sh: no test fixtures in $fixtures: build them with a full (host) build" \
       "(cmake --build build --target dermis_test_fixture_files) or pass their folder" >&2
  exit 2
fi
launcher=()
if command -v ccache > /dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
mkdir -p "$out"
cmake -S "$root" -B "$out" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_TOOLCHAIN_FILE="$root/cmake/toolchains/aarch64-linux-gnu.cmake" "${launcher[@]}" \
  -DDERMIS_BUILD_OFFLINE=OFF -DDERMIS_BUILD_PLUGINS=OFF -DDERMIS_BUILD_GPU=OFF \
  -DDERMIS_TEST_FIXTURE_DIR="$fixtures" > "$out/configure.log" 2>&1 || {
  cat "$out/configure.log" >&2
  exit 1
}
cmake --build "$out" -j"$jobs"
file "$out/bin/test_runtime" | grep -q "ARM aarch64" || {
  echo "cross_aarch64.sh: test_runtime is not an aarch64 program" >&2
  exit 1
}
ctest --test-dir "$out" -j"$jobs" --output-on-failure
