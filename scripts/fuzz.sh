#!/usr/bin/env bash
# The libFuzzer harnesses of tests/fuzz (docs/reliability.md).
#
#   scripts/fuzz.sh [SECONDS] [HARNESS...]   fuzz each harness (default: all) for SECONDS
#                                            (default 600), one at a time, from its seeds
#   scripts/fuzz.sh --replay [HARNESS...]    run every seed and regression input once (CI)
#
# Builds build-fuzz/ with Clang 14 (only the harnesses and the libraries they link), generates
# the seeds from ../shared/data (scripts/fuzz_seeds.py; the .dsurf seeds need build/bin/dermis)
# and the regression inputs (tests/fuzz/make_regressions.py) under build-fuzz/corpus/, and adds
# the reproducers of ../shared/fuzz-findings when present. Limits: -rss_limit_mb=2048
# -malloc_limit_mb=2048 -timeout=30. New inputs go to build-fuzz/corpus/<harness>/found, logs
# to build-fuzz/fuzz-logs/<harness>.log; a crash writes build-fuzz/fuzz-logs/crash-* and fails.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
BUILD=${DERMIS_FUZZ_BUILD:-build-fuzz}
ALL=(obj ply dsurf capi asset_stream gltf assimp)
replay=0
seconds=600
if [[ ${1:-} == --replay ]]; then
  replay=1
  shift
elif [[ ${1:-} =~ ^[0-9]+$ ]]; then
  seconds=$1
  shift
fi
harnesses=("$@")
[[ ${#harnesses[@]} -gt 0 ]] || harnesses=("${ALL[@]}")

cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang-14 \
  -DCMAKE_CXX_COMPILER=clang++-14 -DDERMIS_BUILD_FUZZERS=ON -DDERMIS_BUILD_TESTS=OFF \
  -DDERMIS_BUILD_TOOLS=OFF -DDERMIS_BUILD_BENCH=OFF -DDERMIS_BUILD_GPU=OFF \
  $(command -v ccache >/dev/null && echo -DCMAKE_CXX_COMPILER_LAUNCHER=ccache \
    -DCMAKE_C_COMPILER_LAUNCHER=ccache) >/dev/null
targets=()
for h in "${harnesses[@]}"; do targets+=(--target "fuzz_$h"); done
cmake --build "$BUILD" -j"$(nproc)" "${targets[@]}"

corpus=$BUILD/corpus
rm -rf "$corpus/seeds" "$corpus/regressions"
python3 scripts/fuzz_seeds.py "$corpus/seeds" "${DERMIS:-$ROOT/build/bin/dermis}"
python3 tests/fuzz/make_regressions.py "$corpus/regressions"
findings=$ROOT/../shared/fuzz-findings
# Which reproducers of the campaign each harness replays.
declare -A from_findings=(
  [obj]="obj/*.obj" [dsurf]="dsurf/*.dsurf cli/*.dsurf" [capi]="dsurf/*.dsurf cli/*.dsurf"
  [gltf]="gltf/*.gltf gltf/*.glb cli/*.gltf" [assimp]="assimp/*")
mkdir -p "$BUILD/fuzz-logs"
export ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1:abort_on_error=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$ROOT/tests/fuzz/lsan.supp:print_suppressions=0
limits=(-rss_limit_mb=2048 -malloc_limit_mb=2048 -timeout=30)
status=0
for h in "${harnesses[@]}"; do
  exe=$BUILD/bin/fuzz_$h
  dict=tests/fuzz/$h.dict
  dict_arg=()
  [[ -f $dict ]] && dict_arg=(-dict="$dict")
  inputs=()
  for d in "$corpus/seeds/$h" "$corpus/regressions/$h"; do
    [[ -d $d ]] && inputs+=("$d"/*)
  done
  if [[ -d $findings ]]; then
    for pattern in ${from_findings[$h]:-}; do
      for f in "$findings"/$pattern; do [[ -f $f ]] && inputs+=("$f"); done
    done
  fi
  log=$BUILD/fuzz-logs/$h.log
  if [[ $replay == 1 ]]; then
    if [[ ${#inputs[@]} -eq 0 ]]; then
      echo "fuzz $h: no inputs"
      continue
    fi
    start=$(date +%s)
    if "$exe" "${limits[@]}" "${inputs[@]}" >"$log" 2>&1; then
      echo "fuzz $h: replayed ${#inputs[@]} inputs cleanly in $(($(date +%s) - start)) s"
    else
      echo "fuzz $h: FAILED replaying (log: $log)"
      tail -40 "$log"
      status=1
    fi
    continue
  fi
  work=$corpus/$h/found
  mkdir -p "$work"
  seeds=()
  [[ ${#inputs[@]} -gt 0 ]] && seeds=("${inputs[@]}")
  # Seed files are merged into the working corpus first, then fuzzed for $seconds.
  seed_dir=$corpus/$h/seed_inputs
  rm -rf "$seed_dir"
  mkdir -p "$seed_dir"
  for f in "${seeds[@]}"; do cp "$f" "$seed_dir/"; done
  if "$exe" "${limits[@]}" "${dict_arg[@]}" -max_total_time="$seconds" -print_final_stats=1 \
    -artifact_prefix="$BUILD/fuzz-logs/$h-" "$work" "$seed_dir" >"$log" 2>&1; then
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)
    peak=$(grep -o 'stat::peak_rss_mb: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || true)
    echo "fuzz $h: ${seconds} s clean: ${runs:-?} runs, coverage ${cov:-?} edges, peak RSS ${peak:-?} MB, corpus $(ls "$work" | wc -l) files"
  else
    echo "fuzz $h: FAILED (log: $log)"
    grep -E 'ERROR|SUMMARY|==[0-9]+==' "$log" | head -20
    status=1
  fi
done
exit $status
