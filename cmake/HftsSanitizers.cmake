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
  set(flags -fsanitize=${HFTS_SANITIZE} -fno-omit-frame-pointer -g)
  if(HFTS_SANITIZE STREQUAL "undefined")
    # Every finding fails the run instead of printing and going on. GCC 12
    # with -fsanitize=undefined warns of a use after free inside Eigen's
    # aligned realloc (Eigen/src/Core/util/Memory.h, a false positive of
    # the warning, not a sanitizer finding): kept a warning there.
    list(APPEND flags -fno-sanitize-recover=undefined -Wno-error=use-after-free)
  endif()
  add_compile_options(${flags})
  add_link_options(-fsanitize=${HFTS_SANITIZE})
endif()
