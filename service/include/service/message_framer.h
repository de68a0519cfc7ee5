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
  /// Bytes of the message not finished yet.
  std::size_t kept() const { return kept_; }
  /// Memory held for them (what the connection's input costs beyond its
  /// read buffer): at least kept().
  std::size_t buffered() const { return held_; }
  /// True while a message has begun (a byte other than whitespace) but
  /// not ended.
  bool inMessage() const { return started_; }
  /// True while the unfinished message is an object or array not closed
  /// yet: at the end of the input it cannot be valid JSON.
  bool inUnclosedText() const { return started_ && structured_; }

 private:
  void scan(std::string_view bytes, std::size_t at, std::vector<std::string>& out);
  /// The first position from `i` in `bytes` that can change the framing state.
  std::size_t skipPlain(std::string_view bytes, std::size_t i) const;
  /// Hands on the current message: the kept pieces, then bytes[begin_, end).
  void emit(std::string_view bytes, std::size_t end, std::vector<std::string>& out);
  /// Keeps the unfinished message's bytes of this feed for the next one.
  void keep(std::string_view bytes);
  void forgetKept();

  std::size_t max_bytes_;
  // The unfinished message's bytes from earlier feeds: a first piece of up
  // to 64 KiB, then pieces of 256 KiB, each allocated once. A long message
  // grows without copying what it holds already, and its pieces are
  // separate mappings that go back to the system when freed.
  std::vector<std::string> kept_pieces_;
  std::size_t kept_ = 0;     // bytes in kept_pieces_
  std::size_t held_ = 0;     // their capacity
  std::size_t begin_ = 0;    // where the current message goes on in the bytes being fed
  bool started_ = false;     // a non-whitespace byte of the message was seen
  bool structured_ = false;  // ... and it opened an object or array
  bool after_text_ = false;  // a complete text ended on this line
  JsonNesting nesting_;      // of the current object or array
  bool spent_ = false;
};

}  // namespace hfts::service
