# HFTS_SANITIZE=address|undefined|thread: the project's code is compiled and
# linked with that sanitizer (scripts/sanitize.sh builds into its own
# folder and runs the whole test suite). The Debian libraries stay as they
# are; their reports are suppressed only where tests/sanitizers/ explains why.
set(HFTS_SANITIZE "" CACHE STRING "Sanitizer for the project's code: address, undefined or thread")
set_property(CACHE HFTS_SANITIZE PROPERTY STRINGS "" address undefined thread)

if(HFTS_SANITIZE)
  if(NOT HFTS_SANITIZE MATCHES "^(address|undefined|thread)$")
    message(FATAL_ERROR "HFTS_SANITIZE must be address, undefined or thread, not '${HFTS_SANITIZE}'")
  endif()
  # GCC 12 at scripts/sanitize.sh's -O1 warns that Highway's one-lane
  # vectors in robot/src/sphere_kernel.cpp's scalar target may be used
  # uninitialized (hwy/ops/scalar-inl.h; seen in the thread build): a false
  # positive of the warning at that optimisation level (every lane is
  # written before it is read, and the Release build does not warn), kept
  # a warning there.
  set(flags -fsanitize=${HFTS_SANITIZE} -fno-omit-frame-pointer -g -Wno-error=maybe-uninitialized)
  if(HFTS_SANITIZE STREQUAL "undefined")
    # Every finding fails the run instead of printing and going on. GCC 12
    # with -fsanitize=undefined warns of a use after free inside Eigen's
    # aligned realloc (Eigen/src/Core/util/Memory.h, a false positive of
    # the warning, not a sanitizer finding): kept a warning there.
    list(APPEND flags -fno-sanitize-recover=undefined -Wno-error=use-after-free)
  elseif(HFTS_SANITIZE STREQUAL "thread")
    # GCC 12 warns (-Wtsan) that ThreadSanitizer does not model
    # std::atomic_thread_fence, which Asio's fenced_block uses around every
    # handler (asio/detail/std_fenced_block.hpp). Asio's scheduler also
    # hands handlers over under a mutex, which TSan does model; the code is
    # kept as in production and the warning is not an error in this build.
    list(APPEND flags -Wno-error=tsan)
  endif()
  add_compile_options(${flags})
  add_link_options(-fsanitize=${HFTS_SANITIZE})
endif()
