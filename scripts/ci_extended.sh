#!/usr/bin/env bash
# The checks too long for every CI run (.ci/run keeps under 30 minutes on 2 cores), run before a
# release and after changing a reader, a kernel or the build: run after `bash .ci/run` (it needs
# build/ and build-asan/ from it).
#   1. aarch64: the runtime cross-built with g++-aarch64-linux-gnu, its tests under qemu-aarch64
#      (scripts/cross_aarch64.sh, docs/engine-integration.md);
#   2. the fuzz harnesses' seeds and regression inputs replayed (scripts/fuzz.sh --replay:
#      Clang 14, libFuzzer, ASan+UBSan; docs/reliability.md);
#   3. every reproducer of ../shared/fuzz-findings through the sanitized tool
#      (scripts/replay_findings.sh; skipped with a message when that folder is absent).
set -euo pipefail
cd "$(dirname "$0")/.."
echo "== aarch64: the runtime cross-built (g++-aarch64-linux-gnu), its tests under qemu-aarch64"
bash scripts/cross_aarch64.sh build/tests/fixtures build-aarch64
echo "== Fuzz harnesses: seeds and regression inputs replayed (Clang 14, libFuzzer, ASan+UBSan)"
bash scripts/fuzz.sh --replay
echo "== The reproducers of ../shared/fuzz-findings through the sanitized tool (issue 19)"
rc=0
bash scripts/replay_findings.sh build-asan || rc=$?
if [[ $rc == 77 ]]; then echo "(skipped: no ../shared/fuzz-findings)"; elif [[ $rc != 0 ]]; then exit $rc; fi
