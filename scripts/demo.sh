#!/usr/bin/env bash
# Sets everything up and runs the main job on built-in data: the manifold surface of built-in
# control meshes (a house of quads and triangles, a torus, a 7-sided prism), tessellated to OBJ.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
mkdir -p out/demo
for mesh in house torus prism7; do
  build/bin/dermis tessellate --builtin "$mesh" -o "out/demo/$mesh.obj" --level 16
done
echo "demo: wrote $(ls out/demo/*.obj | tr '\n' ' ')(open them in any OBJ viewer)"
