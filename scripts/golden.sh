#!/usr/bin/env bash
# Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#
# Reference outputs of the `dermis` tool on the shared inputs, to prove that a refactor changes
# no byte of what the tool writes.
#
#   scripts/golden.sh OUT_DIR             write the outputs into OUT_DIR (keep it outside the repo)
#   scripts/golden.sh --compare A B       list the files that differ between two such folders
#
# Set DERMIS_BIN to the folder holding `dermis` (default build/bin). About 30 s on the 2-core
# build machine. The tool runs inside OUT_DIR with relative output names and --threads 2, so no
# file records the folder or the machine; fit reports are kept with their timings stripped (the
# seconds vary from run to run; nothing else in them may). Needs ../shared/data.
set -euo pipefail
caller=$(pwd)
cd "$(dirname "$0")/.."
abs() { [[ "$1" == /* ]] && echo "$1" || echo "$caller/$1"; }

if [[ "${1:-}" == "--compare" ]]; then
  [[ $# -eq 3 ]] || { echo "usage: scripts/golden.sh --compare A B" >&2; exit 2; }
  a=$(abs "$2")
  b=$(abs "$3")
  for d in "$a" "$b"; do
    [[ -d "$d" ]] || { echo "golden: $d is not a folder" >&2; exit 2; }
  done
  differ=0
  same=0
  while IFS= read -r f; do
    if [[ ! -f "$b/$f" ]]; then
      echo "only in $a: $f"
      differ=$((differ + 1))
    elif cmp -s "$a/$f" "$b/$f"; then
      same=$((same + 1))
    else
      echo "differs: $f"
      differ=$((differ + 1))
    fi
  done < <(cd "$a" && find . -type f ! -name 'log.txt' | sed 's|^\./||' | sort)
  while IFS= read -r f; do
    [[ -f "$a/$f" ]] || { echo "only in $b: $f"; differ=$((differ + 1)); }
  done < <(cd "$b" && find . -type f ! -name 'log.txt' | sed 's|^\./||' | sort)
  echo "golden: $same identical, $differ different"
  [[ $differ -eq 0 ]]
  exit
fi

[[ $# -eq 1 && "$1" != -* ]] || { echo "usage: scripts/golden.sh OUT_DIR | --compare A B" >&2; exit 2; }
if [[ ! -d ../shared/data ]]; then
  echo "golden: ../shared/data not found (the shared data folder)" >&2
  exit 77
fi
data=$(cd ../shared/data && pwd -P)
dermis=$(cd "${DERMIS_BIN:-build/bin}" 2>/dev/null && pwd -P)/dermis
[[ -x "$dermis" ]] || { echo "golden: $dermis not found; build first" >&2; exit 2; }
target=$(abs "$1")
mkdir -p "$target"
# The tool runs inside the output folder with relative output names, so that no file records
# the folder's name (reports and inspect output name their inputs).
cd "$target"
out=.
log=log.txt
: > "$log"

run() {  # run CMD...: the tool, output into the log; fails the script on a non-zero exit
  echo "+ dermis $*" >> "$log"
  "$dermis" "$@" >> "$log" 2>&1 || { echo "golden: 'dermis $*' failed (see $log)" >&2; exit 1; }
}
strip_timings() {  # the fit report without its "timings" object (seconds vary between runs)
  python3 - "$1" <<'EOF'
import json, sys
path = sys.argv[1]
with open(path) as f:
    report = json.load(f)
def strip(node):
    if isinstance(node, dict):
        return {k: strip(v) for k, v in node.items() if k not in ("timings", "seconds")}
    if isinstance(node, list):
        return [strip(v) for v in node]
    return node
with open(path, "w") as f:
    json.dump(strip(report), f, indent=1)
    f.write("\n")
EOF
}

start=$SECONDS
# Surfaces: the Stanford bunny (defaults) and the small bunny with a given control-vertex count.
run fit "$data/scans/stanford-bunny.obj" -o "$out/bunny.dsurf" --report "$out/bunny_fit.json" --threads 2 -q -f
strip_timings "$out/bunny_fit.json"
run fit "$data/scans/bunny-npm-1839v.obj" -o "$out/bunny_small.dsurf" --control-vertices 200 --threads 2 \
  --report "$out/bunny_small_fit.json" -q -f
strip_timings "$out/bunny_small_fit.json"
run fit "$data/scans/bun_zipper.ply" -o "$out/bun_zipper.dsurf" --control-vertices 300 --threads 2 -q -f

# Characters: every shared glTF file fitted.
for f in "$data"/gltf/*; do
  name=$(basename "${f%.*}")
  run fit "$f" -o "$out/$name.dsurf" --report "$out/${name}_fit.json" --threads 2 -q -f
  strip_timings "$out/${name}_fit.json"
done

# Export: bound, lod, embedded and baked sweep of two characters.
for name in CesiumMan RiggedFigure; do
  run export "$out/$name.dsurf" -o "$out/${name}_bound.glb" -q -f
  run export "$out/$name.dsurf" -o "$out/${name}_lod.glb" --mode lod --level 4 -q -f
  run export "$out/$name.dsurf" -o "$out/${name}_embed.gltf" --embed -q -f
  run export "$out/$name.dsurf" -o "$out/${name}_sweep.glb" --bake-sweep --fps 10 -q -f
done

# Animate: one clip frame per deformer, bound and lod, OBJ and glTF.
for deformer in sweep lbs dqs; do
  run animate "$out/CesiumMan.dsurf" -o "$out/CesiumMan_$deformer.obj" --time 0.5 \
    --deformer "$deformer" -q -f
  run animate "$out/Fox.dsurf" -o "$out/Fox_$deformer.glb" --clip 1 --time 0.4 \
    --deformer "$deformer" --mode lod --level 3 -q -f
done

# Tessellate: built-in control meshes, an OBJ control mesh, a fitted surface.
for builtin in cube tetrahedron torus prism5 grid house; do
  run tessellate --builtin "$builtin" -o "$out/tess_$builtin.obj" --level 6 -q -f
done
run tessellate --builtin torus -o "$out/tess_torus_c2.obj" --level 4 --blend c2 \
  --chart isodistance -q -f
run tessellate "$data/scans/bunny-npm-1839v.obj" -o "$out/tess_bunny_control.obj" --level 2 -q -f
run tessellate "$out/bunny_small.dsurf" -o "$out/tess_bunny_small.obj" --level 4 -q -f
run tessellate "$out/bunny_small.dsurf" -o "$out/tess_bunny_small_l2.obj" --level 4 \
  --displacement-levels 2 -q -f

# Render: a character contact sheet with a comparison row, a surface with the error heat map.
run render "$out/RiggedFigure.dsurf" -o "$out/render_figure.png" --frames 3 --compare lbs \
  --size 160x160 -q -f
run render "$out/bunny_small.dsurf" -o "$out/render_bunny.png" --heatmap error \
  --reference "$data/scans/bunny-npm-1839v.obj" --size 200x200 --level 4 -q -f

# Inspect and validate as JSON (standard output is the data).
inspect() {  # inspect FILE NAME
  echo "+ dermis inspect --json $1" >> "$log"
  "$dermis" inspect --json "$1" > "$out/$2" 2>> "$log" ||
    { echo "golden: 'dermis inspect --json $1' failed (see $log)" >&2; exit 1; }
}
inspect "$out/CesiumMan.dsurf" inspect_CesiumMan_dsurf.json
inspect "$out/bunny.dsurf" inspect_bunny_dsurf.json
inspect "$out/CesiumMan_bound.glb" inspect_CesiumMan_bound.json
inspect "$data/gltf/Fox.glb" inspect_Fox_glb.json
# validate without the Khronos validator: its version string would tie the bytes to node_modules.
echo "+ dermis validate --json $out/RiggedFigure_lod.glb" >> "$log"
"$dermis" validate --json "$out/RiggedFigure_lod.glb" 2>> "$log" |
  python3 -c 'import json,sys; r=json.load(sys.stdin); r.pop("khronos", None); json.dump(r, sys.stdout, indent=1)' \
    > "$out/validate_RiggedFigure_lod.json" || true

echo "golden: wrote $(find . -type f ! -name log.txt | wc -l) files into $(pwd) in $((SECONDS - start)) s"
