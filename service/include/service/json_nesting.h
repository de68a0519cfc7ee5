#pragma once
// The bracket nesting of JSON text, followed byte by byte.

namespace hfts::service {

/// Counts the objects and arrays open at each byte of a JSON text, skipping
/// brackets inside strings (escaped quotes included). Keeps its state
/// between calls, so a text may arrive in pieces. Does not validate.
class JsonNesting {
 public:
  /// Consumes one byte; returns the depth after it.
  int consume(char c) {
    if (in_string_) {
      if (escaped_)
        escaped_ = false;
      else if (c == '\\')
        escaped_ = true;
      else if (c == '"')
        in_string_ = false;
    } else if (c == '"') {
      in_string_ = true;
    } else if (c == '{' || c == '[') {
      ++depth_;
    } else if (c == '}' || c == ']') {
      --depth_;
    }
    return depth_;
  }
  int depth() const { return depth_; }
  /// Inside a string with no escape pending: only '"' and '\\' change the state.
  bool inPlainString() const { return in_string_ && !escaped_; }
  void reset() { *this = JsonNesting(); }

 private:
  int depth_ = 0;
  bool in_string_ = false;
  bool escaped_ = false;
};

}  // namespace hfts::service
