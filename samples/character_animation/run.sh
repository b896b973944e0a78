#!/usr/bin/env bash
# Paper Fig. 5: a shared glTF character fitted to a displaced surface, animated by the sweep
# deformer (only the control vertices move; patches are refitted, displacements ride along),
# exported with the sweep baked into morph targets, and its clip rendered frame by frame with
# linear blend skinning below for comparison.
#
#   samples/character_animation/run.sh [OUT_DIR] [--small]
#
# Input: ../shared/data/gltf/CesiumMan.glb (--small: RiggedFigure.glb, fewer and smaller
# frames). Exit 77 (skipped) when the shared data is absent. Writes under OUT_DIR (default
# out/character_animation): CHARACTER.dsurf and its fit report, CHARACTER_sweep.glb (plays the
# sweep's motion in any glTF viewer), sweep_vs_lbs.png (top row sweep, bottom row LBS) and
# frames/{sweep,lbs}_NNN.png.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=out/character_animation
name=CesiumMan
frames=8
size=400x400
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
mkdir -p "$out/frames"
"$dermis" fit "$input" -o "$out/$name.dsurf" --report "$out/${name}_fit.json" -q --force
"$dermis" export "$out/$name.dsurf" -o "$out/${name}_sweep.glb" --bake-sweep --fps 15 -q --force
"$dermis" render "$out/$name.dsurf" -o "$out/sweep_vs_lbs.png" --frames "$frames" \
  --deformer sweep --compare lbs --size "$size" --frame-files --force -q
for f in "${name}_sweep.glb" sweep_vs_lbs.png sweep_vs_lbs_000.png; do
  [[ -s "$out/$f" ]] || { echo "character_animation: $out/$f was not written" >&2; exit 1; }
done
echo "character_animation: wrote $out/sweep_vs_lbs.png (top: sweep, bottom: LBS),"
echo "  $out/sweep_vs_lbs_NNN.png (each frame) and $out/${name}_sweep.glb"
