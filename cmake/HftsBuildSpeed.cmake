# How long a fresh build takes on a 2-core machine (docs/performance.md,
# "Building from a fresh clone"): two measured causes, two switches.
#
# Linking: every test program links the preprocess library and through it
# PCL and VTK; GNU ld took 5 s for each of the ~90 programs, LLVM's lld 0.6 s.
# lld is used when it is installed (scripts/setup.sh installs it).
#
# Compiling: most of a source file's time is spent in the headers it shares
# with its neighbours (Eigen, FCL, OMPL, Boost). A unity build compiles a
# library's sources a few at a time in one translation unit. Files that
# Highway's foreach_target includes again by name set
# SKIP_UNITY_BUILD_INCLUSION beside their library. HFTS_UNITY_BUILD=OFF
# builds one file at a time (for tools that want one object per source).
option(HFTS_UNITY_BUILD "Compile each library's sources in batches (unity build)" ON)
if(HFTS_UNITY_BUILD)
  set(CMAKE_UNITY_BUILD ON)
  set(CMAKE_UNITY_BUILD_BATCH_SIZE 6)
endif()

find_program(HFTS_LLD NAMES ld.lld)
if(HFTS_LLD)
  add_link_options(-fuse-ld=lld)
else()
  message(STATUS "ld.lld not found: linking with the default linker (slower; scripts/setup.sh installs lld)")
endif()

# GCC warns when a class of a source file holds a type from its anonymous
# namespace and the file is not the translation unit's main file, which in a
# unity build none of them is: the warning guards against headers only.
if(HFTS_UNITY_BUILD)
  target_compile_options(hfts_warnings INTERFACE $<$<CXX_COMPILER_ID:GNU>:-Wno-subobject-linkage>)
endif()
