#!/usr/bin/env bash
# Paper Fig. 5: a shared glTF character fitted to a displaced surface, animated by the sweep
# deformer (only the control vertices move; patches are refitted, displacements ride along),
# exported with the sweep baked into morph targets, and its clip rendered frame by frame with
# dual-quaternion and linear blend skinning below it for comparison (docs/deformation.md).
#
#   samples/character_animation/run.sh [OUT_DIR] [--small]
#
# Input: ../shared/data/gltf/CesiumMan.glb (--small: RiggedFigure.glb, fewer and smaller
# frames). Exit 77 (skipped) when the shared data is absent. Writes under OUT_DIR (default
# out/character_animation): CHARACTER.dsurf and its fit report, CHARACTER_sweep.glb (plays the
# sweep's motion in any glTF viewer), sweep_dqs_lbs.png (one row per deformer: sweep, DQS, LBS;
# one column per frame) and sweep_dqs_lbs_NNN.png (each picture of it, row by row).
set -euo pipefail
cd "$(dirname "$0")/../.."
out=out/character_animation
name=CesiumMan
frames=8
size=300x300
for arg in "$@"; do
  case "$arg" in
    --small) name=RiggedFigure; frames=3; size=160x160 ;;
    -*) echo "usage: samples/character_animation/run.sh [OUT_DIR] [--small]" >&2; exit 2 ;;
    *) out="$arg" ;;
  esac
done
input=../shared/data/gltf/$name.glb
if [[ ! -f "$input" ]]; then
  echo "character_animation: SKIPPED: $input not found (the shared data folder)" >&2
  exit 77
fi
dermis="${DERMIS_BIN:-build/bin}/dermis"
mkdir -p "$out"
"$dermis" fit "$input" -o "$out/$name.dsurf" --report "$out/${name}_fit.json" -q --force
"$dermis" export "$out/$name.dsurf" -o "$out/${name}_sweep.glb" --bake-sweep --fps 15 -q --force
"$dermis" render "$out/$name.dsurf" -o "$out/sweep_dqs_lbs.png" --frames "$frames" \
  --deformer sweep --compare dqs,lbs --size "$size" --frame-files --force -q
last=$(printf '%03d' $((3 * frames - 1)))
for f in "${name}_sweep.glb" sweep_dqs_lbs.png sweep_dqs_lbs_000.png "sweep_dqs_lbs_$last.png"; do
  [[ -s "$out/$f" ]] || { echo "character_animation: $out/$f was not written" >&2; exit 1; }
done
echo "character_animation: wrote $out/sweep_dqs_lbs.png (rows: sweep, DQS, LBS),"
echo "  $out/sweep_dqs_lbs_NNN.png (each picture) and $out/${name}_sweep.glb"
