#!/usr/bin/env bash
# The README's first command: installs what is missing, builds, and builds
# the HFTS databases of every bundled object, printing a summary table and
# one database's details.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh --target hfts-preprocess
echo
echo "== Building the HFTS databases of objects/meshes into build/databases"
build/bin/hfts-preprocess objects/meshes -o build/databases
echo
echo "== One of them: build/bin/hfts-preprocess --inspect build/databases/mug.h5"
build/bin/hfts-preprocess --inspect build/databases/mug.h5
echo
echo "== The hand reachability map of the KR5 + SDH"
build/bin/hfts-preprocess --hand robots/kr5_sdh/kr5_sdh.json -o build/hand
echo
echo "== The bundled scenes as glTF (open them in any glTF viewer, or scripts/render_glb.py)"
for scene in objects/scenes/*.json; do
  build/bin/hfts-preprocess --export-scene "$scene" "build/$(basename "$scene" .json).glb"
done
echo
echo "To look at the partition: build/bin/hfts-preprocess --export-ply build/databases/mug.h5 mug.ply"
