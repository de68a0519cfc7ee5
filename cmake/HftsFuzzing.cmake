# HFTS_BUILD_FUZZERS: every project library is compiled for libFuzzer with
# AddressSanitizer and UndefinedBehaviorSanitizer; the fuzz targets
# (tests/fuzz/) link the libFuzzer driver. Lean on purpose (-O1, line tables
# only): the sanitizers, not the optimiser, make a fuzz build useful.
# Assertions stay on (-UNDEBUG), so Eigen's bounds checks run too.
option(HFTS_BUILD_FUZZERS "Build the libFuzzer targets of tests/fuzz (needs clang)" OFF)

if(HFTS_BUILD_FUZZERS)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR
      "HFTS_BUILD_FUZZERS needs clang (libFuzzer), not ${CMAKE_CXX_COMPILER_ID}: configure with "
      "-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ (scripts/fuzz.sh does)")
  endif()
  set(HFTS_SANITIZERS address,undefined)
  add_compile_options(-fsanitize=fuzzer-no-link,${HFTS_SANITIZERS}
    -fno-sanitize-recover=undefined -O1 -gline-tables-only -UNDEBUG
    -fsanitize-coverage-ignorelist=${PROJECT_SOURCE_DIR}/tests/fuzz/coverage_ignorelist.txt)
  add_link_options(-fsanitize=${HFTS_SANITIZERS})
endif()
