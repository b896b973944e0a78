#!/usr/bin/env bash
# The built-in demo: a procedurally generated creature (a limb with fine bumps on a 3-joint
# chain, with a bend-and-twist clip) fitted to a displaced surface, animated by the sweep
# deformer, exported to glTF and rendered to PNG frames next to linear blend skinning.
#
#   samples/demo/run_demo.sh [OUT_DIR] [--small]
#
# Needs a build in build/ (or DERMIS_BIN=<dir with dermis and sample_make_creature>). Writes,
# under OUT_DIR (default out/demo):
#   creature.glb              the generated source asset (skinned glTF)
#   creature.dsurf            the fitted character, creature_fit.json its error report
#   creature_skinned.glb      skinned glTF of the displaced surface (any glTF viewer animates it)
#   creature_sweep.glb        the sweep deformer's motion baked into morph targets
#   creature_sweep_web.glb    the same, --quantize --compress (three.js with its meshopt
#                             decoder, Babylon.js, gltfpack; docs/gltf-compression.md)
#   frames/sweep_NNN.png      frames of the clip with the sweep deformer (frames/sweep.png: all)
#   frames/lbs_NNN.png        the same frames with linear blend skinning
#   sweep_vs_lbs.png          both as one contact sheet (top row sweep, bottom row LBS)
#   fit_error.png             the rest pose coloured by the distance to the source mesh
set -euo pipefail
cd "$(dirname "$0")/../.."
out=out/demo
size=480x480
frames=6
small=()
for arg in "$@"; do
  case "$arg" in
    --small) small=(--small); size=160x160; frames=3 ;;
    -*) echo "usage: samples/demo/run_demo.sh [OUT_DIR] [--small]" >&2; exit 2 ;;
    *) out="$arg" ;;
  esac
done
bin="${DERMIS_BIN:-build/bin}"
dermis="$bin/dermis"
mkdir -p "$out/frames"

"$bin/sample_make_creature" "$out/creature.glb" "${small[@]}"
"$dermis" fit "$out/creature.glb" -o "$out/creature.dsurf" --report "$out/creature_fit.json" -q --force
"$dermis" export "$out/creature.dsurf" -o "$out/creature_skinned.glb" -q --force
"$dermis" export "$out/creature.dsurf" -o "$out/creature_sweep.glb" --bake-sweep --fps 15 -q --force
"$dermis" export "$out/creature.dsurf" -o "$out/creature_sweep_web.glb" --bake-sweep --fps 15 \
  --quantize --compress -q --force
plain=$(stat -c %s "$out/creature_sweep.glb")
web=$(stat -c %s "$out/creature_sweep_web.glb")
echo "demo: sweep bake $plain bytes, --quantize --compress $web bytes ($((100 * web / plain)) %)"
(( 100 * web <= 40 * plain )) || { echo "demo: the compressed bake is over 40 % of the plain one" >&2; exit 1; }
for deformer in sweep lbs; do
  "$dermis" render "$out/creature.dsurf" -o "$out/frames/$deformer.png" --deformer "$deformer" \
    --frames "$frames" --columns "$frames" --frame-files --size "$size" --azimuth 0 \
    --elevation 10 --force -q
done
# One sheet: the sweep row above the LBS row.
"$dermis" render "$out/creature.dsurf" -o "$out/sweep_vs_lbs.png" --frames "$frames" \
  --deformer sweep --compare lbs --size "$size" --azimuth 0 --elevation 10 --force -q
"$dermis" render "$out/creature.dsurf" -o "$out/fit_error.png" --heatmap error --size "$size" \
  --clip rest --force -q
for f in creature.glb creature.dsurf creature_fit.json creature_skinned.glb creature_sweep.glb \
         creature_sweep_web.glb \
         sweep_vs_lbs.png fit_error.png frames/sweep_000.png frames/lbs_000.png; do
  [[ -s "$out/$f" ]] || { echo "demo: $out/$f was not written" >&2; exit 1; }
done
echo "demo: wrote $out/creature.glb, creature.dsurf (report creature_fit.json),"
echo "      creature_skinned.glb and creature_sweep.glb (open them in any glTF viewer),"
echo "      $out/frames/sweep_*.png and lbs_*.png (the clip, sweep vs LBS), fit_error.png"
