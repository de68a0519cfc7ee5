#!/usr/bin/env bash
# The README's first command: installs what is missing, builds, builds the
# HFTS databases of every bundled object and the hand reachability map,
# then plans a grasp and a path to it in each bundled scene.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh --target hfts-preprocess hfts-bench
echo
echo "== Building the HFTS databases of objects/meshes into build/databases"
build/bin/hfts-preprocess objects/meshes -o build/databases
echo
echo "== One of them: build/bin/hfts-preprocess --inspect build/databases/mug.h5"
build/bin/hfts-preprocess --inspect build/databases/mug.h5
echo
echo "== The hand reachability map of the KR5 + SDH"
build/bin/hfts-preprocess --hand robots/kr5_sdh/kr5_sdh.json -o build/databases
echo
echo "== The bundled scenes as glTF (open them in any glTF viewer, or scripts/render_glb.py)"
for scene in objects/scenes/*.json; do
  build/bin/hfts-preprocess --export-scene "$scene" "build/$(basename "$scene" .json).glb"
done
echo
echo "== Grasp and motion planning in each bundled scene (coupled planner, seed 1)"
build/bin/hfts-bench --db build/databases --algorithms coupled --runs 1 --time-limit 30 \
  --out build/demo_plans.csv
echo
echo "To look at the partition: build/bin/hfts-preprocess --export-ply build/databases/mug.h5 mug.ply"
