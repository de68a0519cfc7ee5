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
echo "To look at the partition: build/bin/hfts-preprocess --export-ply build/databases/mug.h5 mug.ply"
