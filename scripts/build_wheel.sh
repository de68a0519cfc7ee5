#!/usr/bin/env bash
# Builds the wheel of the Python module hfts (docs/python.md) offline into
# dist/ of the current folder (or the folder given as the only argument):
# Debian's python3-build without an isolated environment (no PyPI), CMake
# building the extension.
# HFTS_CMAKE_BUILD_DIR may name a configured build folder to reuse (the
# tests reuse build/); by default the extension is built in build/wheel.
# Install it with:
#   /usr/bin/python3 -m venv --system-site-packages VENV
#   VENV/bin/pip install --no-index dist/hfts-*.whl
set -euo pipefail
# Paths given relative to where the script was called from.
if [[ -n "${HFTS_CMAKE_BUILD_DIR:-}" ]]; then
  HFTS_CMAKE_BUILD_DIR="$(cd "$HFTS_CMAKE_BUILD_DIR" && pwd)"
  export HFTS_CMAKE_BUILD_DIR
fi
mkdir -p "${1:-dist}"
out="$(cd "${1:-dist}" && pwd)"
cd "$(dirname "$0")/.."
scripts/setup.sh >/dev/null
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# setuptools writes its build and egg-info folders beside setup.py: build a
# copy of python/ so that the checkout stays clean.
cp -r python "$work/python"
HFTS_SOURCE_ROOT="$PWD" /usr/bin/python3 -m build --no-isolation --wheel --outdir "$out" "$work/python"
