#!/usr/bin/env bash
# Replays every reproducer of ../shared/fuzz-findings (issue 19) through the dermis tool built
# with AddressSanitizer and UBSan, and the C API reproducer through the sanitized runtime.
# Each run must end cleanly: exit 0 or 1 (2 for usage), a message naming the file when it
# fails, no sanitizer report, no timeout (120 s), RSS under 4 GiB, no output left behind by a
# failed run.
#
#   scripts/replay_findings.sh [BUILD_DIR]   (default build-asan, configured with
#                                             -DCMAKE_BUILD_TYPE=Debug -DDERMIS_SANITIZE=ON)
# Exit 0 when every run is clean, 1 otherwise, 77 when ../shared/fuzz-findings is absent.
set -uo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build-asan}
FINDINGS=../shared/fuzz-findings
DATA=../shared/data
D=$PWD/$BUILD/bin/dermis
if [[ ! -d $FINDINGS ]]; then
  echo "replay_findings: $FINDINGS is absent: nothing to replay"
  exit 77
fi
if [[ ! -x $D ]]; then
  echo "replay_findings: $D not built (cmake -S . -B $BUILD -DCMAKE_BUILD_TYPE=Debug -DDERMIS_SANITIZE=ON && cmake --build $BUILD --target dermis dermis_runtime)"
  exit 1
fi
export ASAN_OPTIONS=detect_leaks=1:hard_rss_limit_mb=4096:abort_on_error=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
runs=0
bad=0

# check NAME CMD...: runs CMD in $WORK/out (emptied first), records a failure if it crashes,
# reports a sanitizer error, times out, exits other than 0/1/2, or leaves files after failing.
check() {
  local name=$1
  shift
  rm -rf "$WORK/out"
  mkdir -p "$WORK/out"
  local start=$SECONDS
  timeout 120 "$@" >"$WORK/log" 2>&1
  local rc=$?
  local why=""
  if grep -qE 'ERROR: (AddressSanitizer|LeakSanitizer)|runtime error:|SUMMARY: .*Sanitizer' "$WORK/log"; then
    why="sanitizer report"
  elif [[ $rc == 124 ]]; then
    why="timed out"
  elif [[ $rc -gt 2 ]]; then
    why="exit $rc"
  elif [[ $rc == 1 ]] && [[ -n $(ls -A "$WORK/out") ]]; then
    why="failed but left $(ls "$WORK/out")"
  elif [[ $rc == 1 ]] && ! grep -qiE 'error|invalid|"valid": false' "$WORK/log"; then
    why="failed without an error message"
  fi
  runs=$((runs + 1))
  if [[ -n $why ]]; then
    bad=$((bad + 1))
    echo "FAIL  $name: $why"
    sed 's/^/      /' "$WORK/log" | head -15
  else
    printf 'ok    %-70s exit %d  %3d s  %s\n' "$name" "$rc" $((SECONDS - start)) \
      "$(grep -m1 -o 'error: .*' "$WORK/log" | cut -c1-110)"
  fi
}

O=$WORK/out
for f in "$FINDINGS"/dsurf/*.dsurf "$FINDINGS"/cli/*.dsurf; do
  n=${f#"$FINDINGS"/}
  check "validate $n" "$D" validate "$f"
  check "inspect --json $n" "$D" inspect --json "$f"
  check "tessellate $n" "$D" tessellate "$f" -o "$O/t.obj" --level 2
  check "render $n" "$D" render "$f" -o "$O/r.png" --size 64x64
  check "export $n" "$D" export "$f" -o "$O/e.glb"
  check "export --bake-sweep $n" "$D" export "$f" -o "$O/b.glb" --bake-sweep
done
for f in "$FINDINGS"/gltf/* "$FINDINGS"/cli/*.gltf "$FINDINGS"/assimp/* "$FINDINGS"/obj/*; do
  n=${f#"$FINDINGS"/}
  check "validate --json $n" "$D" validate --json "$f"
  check "inspect $n" "$D" inspect "$f"
  check "fit $n" "$D" fit "$f" -o "$O/f.dsurf" --report "$O/f.json" --threads 2
done
for f in "$FINDINGS"/obj/*.obj; do
  n=${f#"$FINDINGS"/}
  check "tessellate $n" "$D" tessellate "$f" -o "$O/t.obj"
done
# The long clip fitted, then baked (the budget on frames x vertices).
if "$D" fit "$FINDINGS/cli/long_clip.gltf" -o "$WORK/long_clip.dsurf" -q >/dev/null 2>&1; then
  check "export --bake-sweep (fitted cli/long_clip.gltf)" "$D" export "$WORK/long_clip.dsurf" -o "$O/b.glb" --bake-sweep
fi
# Non-UTF-8 file names (cli/nonutf8_path.sh, run here with checks).
if [[ -f $DATA/gltf/RiggedSimple.glb ]]; then
  bad_name=$WORK/$(printf 'bad\377.glb')
  cp "$DATA/gltf/RiggedSimple.glb" "$bad_name"
  check "validate --json (non-UTF-8 name)" "$D" validate --json "$bad_name"
  check "fit --report (non-UTF-8 name)" "$D" fit "$bad_name" -o "$O/x.dsurf" --report "$O/r.json"
fi
# The 250,000-vertex face (cli/make_big_inputs.py), written into the scratch folder.
(cd "$WORK" && python3 "$OLDPWD/$FINDINGS/cli/make_big_inputs.py")
check "validate obj_face250k_circle.obj" "$D" validate "$WORK/obj_face250k_circle.obj"
check "tessellate obj_face250k_circle.obj" "$D" tessellate "$WORK/obj_face250k_circle.obj" -o "$O/t.obj" --level 1
# Misleading inputs (finding 13): a directory named .glb, a device, PLY/GLB given to tessellate.
mkdir -p "$WORK/dir.glb"
check "fit (a directory named dir.glb)" "$D" fit "$WORK/dir.glb" -o "$O/x.dsurf"
check "validate /dev/zero" "$D" validate /dev/zero
check "tessellate /dev/zero" "$D" tessellate /dev/zero -o "$O/t.obj"
[[ -f $DATA/scans/bun_zipper.ply ]] && check "tessellate bun_zipper.ply" "$D" tessellate "$DATA/scans/bun_zipper.ply" -o "$O/t.obj" --level 1
[[ -f $DATA/gltf/Fox.glb ]] && check "tessellate Fox.glb" "$D" tessellate "$DATA/gltf/Fox.glb" -o "$O/t.obj"
# The C API reproducer against the sanitized runtime.
lib=$BUILD/lib
if [[ -f $lib/libdermis_runtime.a ]]; then
  if cc -fsanitize=address,undefined -Isdk/include "$FINDINGS/dsurf/capi_load_then_instance.c" \
    "$lib/libdermis_runtime.a" "$lib/libdermis_deform.a" "$lib/libdermis_asset.a" \
    "$lib/libdermis_core.a" -lstdc++ -lm -lpthread -o "$WORK/capi" 2>"$WORK/cc.log"; then
    for f in "$FINDINGS"/dsurf/*.dsurf; do
      check "C API load + instance ${f#"$FINDINGS"/}" "$WORK/capi" "$f"
    done
  else
    bad=$((bad + 1))
    echo "FAIL  could not build the C API reproducer:"
    head -5 "$WORK/cc.log"
  fi
fi
echo "replay_findings: $runs runs, $((runs - bad)) clean, $bad failed"
[[ $bad == 0 ]]
