#!/usr/bin/env bash
# Builds the project with one sanitizer into its own folder and runs the
# whole test suite (ctest) under it:
#
#   scripts/sanitize.sh asan|ubsan|tsan [more ctest arguments]
#
# asan: AddressSanitizer with LeakSanitizer (build-asan/), ubsan:
# UndefinedBehaviorSanitizer, every finding fatal (build-ubsan/), tsan:
# ThreadSanitizer (build-tsan/). The compiler is g++ at -O1 with
# assertions on. Reports of third-party code are suppressed only by the
# commented entries of tests/sanitizers/*.supp. Exits non-zero when a test
# fails or a sanitizer reports.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

case "${1:-}" in
  asan) sanitizer=address ;;
  ubsan) sanitizer=undefined ;;
  tsan) sanitizer=thread ;;
  *) sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 2 ;;
esac
kind=$1
shift
build=build-$kind

scripts/setup.sh
supp=$root/tests/sanitizers
# Tests that measure resident memory skip that part under asan and tsan.
export HFTS_SANITIZER=$sanitizer
# The test programs run while building (gtest discovery) as well as under
# ctest, so the options hold for both.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:detect_stack_use_after_return=1:strict_init_order=1"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$supp/ubsan.supp"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$supp/tsan.supp"

# Without the Python module: an instrumented extension does not load into
# Debian's uninstrumented python3.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1" \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1" -DHFTS_SANITIZE="$sanitizer" -DHFTS_BUILD_PYTHON=OFF >/dev/null
echo "sanitize: building $build ($sanitizer)"
cmake --build "$build" -j "$(nproc)"
echo "sanitize: running the tests under $sanitizer"
cd "$build"
ctest --output-on-failure -j "$(nproc)" --timeout 1800 "$@"
