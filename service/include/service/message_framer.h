#pragma once
// Splits the byte stream of a connection into JSON-RPC messages.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "service/json_nesting.h"

namespace hfts::service {

/// Cuts a byte stream into messages: one per line ("\n"; a "\r" before it
/// is whitespace), and also a complete JSON object or array that is not
/// followed by a newline (so a client may send one JSON text and wait).
/// A raw newline always ends a message, so a truncated text on a line is
/// handed on (and fails to parse) instead of waiting for more input.
///
/// An empty or blank line is handed on as an empty string, except the
/// whitespace that follows a complete text on the same line. The work is
/// linear in the input: the nesting depth outside strings is tracked
/// across calls.
class MessageFramer {
 public:
  /// `maxMessageBytes` bounds one message, including bytes not yet framed.
  explicit MessageFramer(std::size_t maxMessageBytes);

  /// Appends `bytes` and moves the complete messages to `out`. Returns
  /// false once the message being read exceeds the limit; the framer is
  /// then spent (the connection should be closed).
  bool feed(std::string_view bytes, std::vector<std::string>& out);

  /// The incomplete message at the end of the input; empty when only
  /// whitespace is left. Clears it.
  std::string takeRemainder();
  /// Forgets the incomplete message at the end of the input (and its buffer).
  void dropRemainder();

  std::size_t maxMessageBytes() const { return max_bytes_; }
  /// Bytes held for the message not finished yet (what the connection's
  /// input costs in memory beyond its read buffer).
  std::size_t buffered() const { return pending_.size(); }
  /// True while a message has begun (a byte other than whitespace) but
  /// not ended.
  bool inMessage() const { return started_; }
  /// True while the unfinished message is an object or array not closed
  /// yet: at the end of the input it cannot be valid JSON.
  bool inUnclosedText() const { return started_ && structured_; }

 private:
  void scan(char c, std::size_t at, std::vector<std::string>& out);
  /// The first position from `i` that can change the framing state.
  std::size_t skipPlain(std::size_t i) const;
  void emit(std::size_t end, std::vector<std::string>& out);

  std::size_t max_bytes_;
  std::string pending_;      // bytes from the start of the current message
  std::size_t begin_ = 0;    // start of the current message in pending_
  bool started_ = false;     // a non-whitespace byte of the message was seen
  bool structured_ = false;  // ... and it opened an object or array
  bool after_text_ = false;  // a complete text ended on this line
  JsonNesting nesting_;      // of the current object or array
  bool spent_ = false;
};

}  // namespace hfts::service
