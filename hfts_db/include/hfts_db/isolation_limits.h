#pragma once
// What a child process of runIsolated (hfts_db/isolated_call.h) may use; on
// its own so that triangle_mesh.h, which is widely included, needs no more.

#include <chrono>
#include <cstddef>

namespace hfts {

/// What the child may use.
struct IsolationLimits {
  std::chrono::milliseconds time{60'000};  ///< wall time; the child is killed beyond it
  /// Address space the child may add to what it inherits (RLIMIT_AS); 0:
  /// no limit. Beyond it allocations fail (std::bad_alloc in `work`).
  std::size_t extra_memory_bytes = 0;
};

}  // namespace hfts
