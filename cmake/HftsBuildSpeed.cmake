# How long a fresh build takes on a 2-core machine (docs/performance.md,
# "Building from a fresh clone").
#
# Compiling: most of a source file's time is spent in the headers it shares
# with its neighbours (Eigen, FCL, OMPL, Boost). A unity build compiles a
# library's sources a few at a time in one translation unit (a clean build
# 13 min -> 9.7 min). Files that Highway's foreach_target includes again by
# name set SKIP_UNITY_BUILD_INCLUSION beside their library.
# HFTS_UNITY_BUILD=OFF builds one file at a time (for tools that want one
# object per source).
#
# Linking: every test program links the preprocess library and through it
# PCL and VTK; LLVM's lld links one in 0.6 s where GNU ld takes 5 s (a small
# share of the whole build). lld is used when it is installed
# (scripts/setup.sh installs it).
option(HFTS_UNITY_BUILD "Compile each library's sources in batches (unity build)" ON)
if(HFTS_UNITY_BUILD)
  set(CMAKE_UNITY_BUILD ON)
  set(CMAKE_UNITY_BUILD_BATCH_SIZE 6)
  # GCC warns when a class of a source file holds a type from its anonymous
  # namespace and the file is not the translation unit's main file, which in
  # a unity build none of them is: the warning guards against headers only.
  target_compile_options(hfts_warnings INTERFACE $<$<CXX_COMPILER_ID:GNU>:-Wno-subobject-linkage>)
endif()

find_program(HFTS_LLD NAMES ld.lld)
if(HFTS_LLD)
  add_link_options(-fuse-ld=lld)
else()
  message(STATUS "ld.lld not found: linking with the default linker (slower; scripts/setup.sh installs lld)")
endif()
