#!/usr/bin/env bash
# The README's second command: installs what is missing, builds, and runs
# every test (GoogleTest suites, CLI and Python tests, format check) with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
scripts/fuzz.sh --build-only  # the fuzz targets of the fuzz_short test (build-fuzz/, clang)
cd build
ctest --output-on-failure -j "$(nproc)" --timeout 600
