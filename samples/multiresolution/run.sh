#!/usr/bin/env bash
# Paper Fig. 6: the Stanford bunny fitted with 540 control vertices, shown with 0, 2, 4, 5 and
# all displacement levels (runtime level of detail: the same .dsurf, fewer B-spline levels),
# coloured by the distance to the scan, with the error of each level in a table.
#
#   samples/multiresolution/run.sh [OUT_DIR] [--small]
#
# Input: ../shared/data/scans/stanford-bunny.obj (--small: bunny-npm-1839v.obj, 200 control
# vertices, smaller pictures). Exit 77 (skipped) when the shared data is absent. Writes under
# OUT_DIR (default out/multiresolution): bunny.dsurf, bunny_fit.json, levels.png (one view per
# level), levels_NNN.png and $out/errors.md (distance from the surface to the scan per level).
set -euo pipefail
cd "$(dirname "$0")/../.."
out=out/multiresolution
input=../shared/data/scans/stanford-bunny.obj
control=540
size=480x480
series=0,2,4,5,-1
for arg in "$@"; do
  case "$arg" in
    --small) input=../shared/data/scans/bunny-npm-1839v.obj; control=200; size=200x200
             series=0,2,-1 ;;
    -*) echo "usage: samples/multiresolution/run.sh [OUT_DIR] [--small]" >&2; exit 2 ;;
    *) out="$arg" ;;
  esac
done
if [[ ! -f "$input" ]]; then
  echo "multiresolution: SKIPPED: $input not found (the shared data folder)" >&2
  exit 77
fi
dermis="${DERMIS_BIN:-build/bin}/dermis"
mkdir -p "$out"
"$dermis" fit "$input" -o "$out/bunny.dsurf" --control-vertices "$control" \
  --report "$out/bunny_fit.json" -q --force
"$dermis" render "$out/bunny.dsurf" -o "$out/levels.png" --series "$series" --heatmap error \
  --reference "$input" --size "$size" --level 8 --azimuth 20 --elevation 10 --frame-files \
  --force 2> "$out/render.log"
{
  echo "| displacement levels | distance from the surface to the scan (model units) |"
  echo "|---|---|"
  sed -n 's/^dermis render: displacement \(.*\): distance to data \(.*\)$/| \1 | \2 |/p' \
    "$out/render.log"
} > "$out/errors.md"
[[ -s "$out/levels.png" && $(wc -l < "$out/errors.md") -gt 2 ]] || {
  echo "multiresolution: no pictures or no error table (see $out/render.log)" >&2; exit 1; }
cat "$out/errors.md"
echo "multiresolution: wrote $out/levels.png, $out/levels_NNN.png and $out/errors.md"
