#!/usr/bin/env bash
# A runtime-only build (issue 17, docs/engine-integration.md "Runtime-only builds"): the runtime
# alone, configured with every offline package hidden from find_package (so it provably needs
# only a C++17 compiler and GLM), built warning-free, and the runtime's own tests run on the
# fixture files of a full build.
#   bash scripts/runtime_only.sh [FIXTURE_DIR] [BUILD_DIR]
# CC / CXX choose the compiler (CI: clang-14 / clang++-14). FIXTURE_DIR defaults to
# build/tests/fixtures, BUILD_DIR to build-runtime-only. Exit status: ctest's.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
fixtures=$(realpath -m "${1:-$root/build/tests/fixtures}")
out=$(realpath -m "${2:-$root/build-runtime-only}")
jobs=${DERMIS_JOBS:-$(nproc)}
if [ ! -f "$fixtures/cylinders.dsurf" ]; then
  echo "runtime_only.sh: no test fixtures in $fixtures: build them with a full build" \
       "(cmake --build build --target dermis_test_fixture_files) or pass their folder" >&2
  exit 2
fi
hidden=()
for p in Eigen3 meshoptimizer lemon TinyGLTF assimp Vulkan CLI11 nlohmann_json; do
  hidden+=("-DCMAKE_DISABLE_FIND_PACKAGE_$p=ON")
done
launcher=()
if command -v ccache > /dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
mkdir -p "$out"
cmake -S "$root" -B "$out" -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" "${hidden[@]}" \
  -DDERMIS_BUILD_OFFLINE=OFF -DDERMIS_BUILD_PLUGINS=OFF -DDERMIS_BUILD_GPU=OFF \
  -DDERMIS_TEST_FIXTURE_DIR="$fixtures" > "$out/configure.log" 2>&1 || {
  cat "$out/configure.log" >&2
  exit 1
}
cmake --build "$out" -j"$jobs"
ctest --test-dir "$out" -j"$jobs" --output-on-failure
