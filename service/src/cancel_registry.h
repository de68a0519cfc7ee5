#pragma once
// The plans of one connection that can still be cancelled, by request id.

#include <map>
#include <string>

#include "worker_pool.h"

namespace hfts::service {

/// Keys are the ids' JSON texts (so 1 and "1" differ). Used only on the
/// server's I/O thread.
class CancelRegistry {
 public:
  void add(const std::string& id, CancelFlag flag) { flags_.emplace(id, std::move(flag)); }
  void remove(const std::string& id, const CancelFlag& flag) {
    for (auto [it, end] = flags_.equal_range(id); it != end; ++it)
      if (it->second == flag) {
        flags_.erase(it);
        return;
      }
  }
  /// Raises the flags of every plan with this id; false when there is none.
  bool cancel(const std::string& id) {
    const auto [begin, end] = flags_.equal_range(id);
    for (auto it = begin; it != end; ++it) it->second->store(true);
    return begin != end;
  }
  void cancelAll() {
    for (auto& entry : flags_) entry.second->store(true);
  }
  bool empty() const { return flags_.empty(); }

 private:
  std::multimap<std::string, CancelFlag> flags_;
};

}  // namespace hfts::service
