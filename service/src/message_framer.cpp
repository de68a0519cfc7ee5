#include "service/message_framer.h"

#include <algorithm>
#include <cstring>

namespace hfts::service {
namespace {

/// The first piece of a kept message grows as its bytes arrive, up to this
/// size; most messages fit in it.
constexpr std::size_t kFirstPieceBytes = 64u << 10;
/// Further pieces are allocated at this size at once: above glibc's mmap
/// threshold (128 KiB, set by hfts-server), so each is its own mapping
/// that free() returns to the system.
constexpr std::size_t kPieceBytes = 256u << 10;

bool isJsonWhitespace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

}  // namespace

MessageFramer::MessageFramer(std::size_t maxMessageBytes) : max_bytes_(maxMessageBytes) {}

bool MessageFramer::feed(std::string_view bytes, std::vector<std::string>& out) {
  if (spent_) return false;
  begin_ = 0;  // an unfinished message goes on with the first byte
  bool over = false;
  for (std::size_t i = skipPlain(bytes, 0); i < bytes.size() && !over;
       i = skipPlain(bytes, i + 1)) {
    // The message with byte i (a newline ends it and is not part of it).
    over = kept_ + i - begin_ + (bytes[i] == '\n' ? 0 : 1) > max_bytes_;
    if (!over) scan(bytes, i, out);
  }
  if (over || kept_ + bytes.size() - begin_ > max_bytes_) {
    spent_ = true;
    dropRemainder();
    return false;
  }
  keep(bytes.substr(begin_));
  return true;
}

std::size_t MessageFramer::skipPlain(std::string_view bytes, std::size_t i) const {
  // Bytes that cannot end the message or change its nesting are skipped
  // without the state machine: the bulk of a long string or scalar.
  const char* text = bytes.data();
  const std::size_t end = bytes.size();
  if (!started_ || i >= end) return i;
  if (!structured_) {
    const void* newline = std::memchr(text + i, '\n', end - i);
    return newline == nullptr ? end
                              : static_cast<std::size_t>(static_cast<const char*>(newline) - text);
  }
  if (!nesting_.inPlainString()) return i;
  std::size_t next = end;  // the first '"', '\\' or newline: memchr is vectorised
  for (const char c : {'"', '\\', '\n'})
    if (const void* at = std::memchr(text + i, c, next - i))
      next = static_cast<std::size_t>(static_cast<const char*>(at) - text);
  return next;
}

void MessageFramer::scan(std::string_view bytes, std::size_t at, std::vector<std::string>& out) {
  const char c = bytes[at];
  if (c == '\n') {
    const bool blank = !started_;
    if (!blank) {
      emit(bytes, at, out);
    } else if (!after_text_) {
      out.emplace_back();  // a blank line (only whitespace after a complete text is not one)
    }
    forgetKept();
    begin_ = at + 1;
    after_text_ = false;
    started_ = structured_ = false;
    return;
  }
  if (!started_) {
    if (isJsonWhitespace(c)) return;
    started_ = true;
    after_text_ = false;
    structured_ = c == '{' || c == '[';
    nesting_.reset();
    nesting_.consume(c);
    return;
  }
  // A scalar or garbage waits for the newline; an object or array ends
  // where its nesting returns to zero.
  if (structured_ && nesting_.consume(c) == 0) {
    emit(bytes, at + 1, out);
    forgetKept();
    begin_ = at + 1;
    started_ = structured_ = false;
    after_text_ = true;
  }
}

void MessageFramer::emit(std::string_view bytes, std::size_t end, std::vector<std::string>& out) {
  std::string& message = out.emplace_back();
  message.reserve(kept_ + end - begin_);
  for (const std::string& piece : kept_pieces_) message += piece;
  message.append(bytes.substr(begin_, end - begin_));
}

void MessageFramer::keep(std::string_view bytes) {
  const auto size = [this] { return kept_pieces_.size() == 1 ? kFirstPieceBytes : kPieceBytes; };
  while (!bytes.empty()) {
    if (kept_pieces_.empty() || kept_pieces_.back().size() == size()) {
      std::string& fresh = kept_pieces_.emplace_back();
      if (kept_pieces_.size() > 1) fresh.reserve(kPieceBytes);
      held_ += fresh.capacity();
    }
    std::string& piece = kept_pieces_.back();
    const std::size_t capacity = piece.capacity();
    const std::size_t n = std::min(bytes.size(), size() - piece.size());
    if (piece.size() + n > capacity) {
      // The first piece: doubling, but not beyond its size (a string's own
      // growth would double past it).
      std::string larger;
      larger.reserve(std::min(kFirstPieceBytes, std::max(2 * capacity, piece.size() + n)));
      larger.append(piece);
      piece.swap(larger);
    }
    piece.append(bytes.substr(0, n));
    bytes.remove_prefix(n);
    kept_ += n;
    held_ += piece.capacity() - capacity;
  }
}

void MessageFramer::forgetKept() {
  kept_pieces_.clear();
  if (kept_pieces_.capacity() > 16) kept_pieces_.shrink_to_fit();
  kept_ = held_ = 0;
}

std::string MessageFramer::takeRemainder() {
  std::string rest;
  if (started_) {
    rest.reserve(kept_);
    for (const std::string& piece : kept_pieces_) rest += piece;
  }
  dropRemainder();
  return rest;
}

void MessageFramer::dropRemainder() {
  forgetKept();
  started_ = structured_ = after_text_ = false;
}

}  // namespace hfts::service
