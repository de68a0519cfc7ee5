# Warnings are errors for project code. Third-party headers come in through
# imported targets or SYSTEM include directories, so they are not affected.
add_library(hfts_warnings INTERFACE)
target_compile_options(hfts_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wold-style-cast
  -Wcast-align -Wunused -Woverloaded-virtual -Wnull-dereference
  -Wdouble-promotion -Wformat=2 -Werror)
