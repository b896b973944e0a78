#!/usr/bin/env bash
# Sets everything up and runs the main job on built-in data: the demo creature (a procedural
# limb with fine bumps and a bend-and-twist clip) fitted to a displaced surface, animated by the
# sweep deformer, exported to glTF and rendered to PNG frames next to linear blend skinning
# (samples/demo/run_demo.sh); then the manifold surface of built-in control meshes tessellated
# to OBJ and a fit of a dense mesh (.dsurf + JSON report).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
mkdir -p out/demo
bash samples/demo/run_demo.sh out/demo
for mesh in house torus prism7; do
  build/bin/dermis tessellate --builtin "$mesh" -o "out/demo/$mesh.obj" --level 16 --force
done
# Fit: a dense mesh (the torus tessellated at level 12) -> automatic control mesh +
# displacements (.dsurf) with an error report, then the fitted surface tessellated back.
build/bin/dermis tessellate --builtin torus -o out/demo/torus_dense.obj --level 12 -q --force
build/bin/dermis fit out/demo/torus_dense.obj -o out/demo/torus_fit.dsurf --control-vertices 200 --force \
  --report out/demo/torus_fit.json
build/bin/dermis tessellate out/demo/torus_fit.dsurf -o out/demo/torus_fit.obj --level 8 --force
echo "demo: wrote $(ls out/demo/*.obj | tr '\n' ' ')(open them in any OBJ viewer)"
echo "demo: everything is in $(pwd)/out/demo: creature_skinned.glb, creature_sweep.glb,"
echo "      sweep_vs_lbs.png, frames/*.png, fit_error.png"
