#!/usr/bin/env bash
# Sets everything up, builds and runs the whole test suite (Catch2 under ctest).
# Tests that need ../shared/data say so and skip when it is absent.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/setup_js.sh
build_dir="${DERMIS_BUILD_DIR:-build}"
ctest --test-dir "$build_dir" --output-on-failure -j"$(nproc)"
