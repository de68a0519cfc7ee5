#!/usr/bin/env bash
# Configures and builds the project into build/ (programs in build/bin/).
# Extra arguments are passed to `cmake --build` (e.g. --target hfts-preprocess).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" "$@"
