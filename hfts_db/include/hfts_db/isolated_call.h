#pragma once
// Runs a piece of third-party code in a child process, for code that may
// crash or hang on malformed input (assimp's importers read out of bounds
// on some malformed PLY files, docs/reliability.md): the child's crash or
// hang becomes an exception in the caller instead of ending the program.

#include <functional>
#include <stdexcept>
#include <string>

#include "hfts_db/isolation_limits.h"

namespace hfts {

/// How an isolated call failed: `work` threw (message is its what()), or the
/// child ended without finishing (a signal, an exit, the time limit).
class IsolatedCallError : public std::runtime_error {
 public:
  enum class Kind { kThrew, kCrashed, kTimedOut };
  IsolatedCallError(Kind kind, const std::string& message)
      : std::runtime_error(message), kind_(kind) {}
  Kind kind() const { return kind_; }

 private:
  Kind kind_;
};

/// Calls `work` in a forked child and returns the bytes it returned. The
/// child only runs `work` (with the default action for crash signals, so a
/// crash ends it silently, even under a sanitizer), writes the result to a
/// pipe and leaves with _exit; memory is the parent's, copied on write.
/// Throws IsolatedCallError when `work` throws, when the child dies (the
/// message names the signal) or when it has not finished within the time
/// limit (it is then killed). May be called from several threads at once
/// (hfts-preprocess --jobs): the child has only the calling thread, and
/// what it uses besides `work` (malloc, stdio) glibc keeps usable across
/// fork; `work` must not wait for other threads. Exception: in a GCC
/// AddressSanitizer build (whose allocator is not fork-safe) a process with
/// several threads runs `work` in place, without the isolation.
std::string runIsolated(const std::function<std::string()>& work, const IsolationLimits& limits);

}  // namespace hfts
