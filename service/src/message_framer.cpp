#include "service/message_framer.h"

#include <cstring>

namespace hfts::service {
namespace {

/// Buffer capacity kept between messages without asking whether it is used.
constexpr std::size_t kKeptCapacity = 256u << 10;

bool isJsonWhitespace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

}  // namespace

MessageFramer::MessageFramer(std::size_t maxMessageBytes) : max_bytes_(maxMessageBytes) {}

bool MessageFramer::feed(std::string_view bytes, std::vector<std::string>& out) {
  if (spent_) return false;
  const std::size_t first = pending_.size();
  pending_.append(bytes);
  bool over = false;
  for (std::size_t i = skipPlain(first); i < pending_.size() && !over; i = skipPlain(i + 1)) {
    // The message with byte i (a newline ends it and is not part of it).
    over = i - begin_ + (pending_[i] == '\n' ? 0 : 1) > max_bytes_;
    if (!over) scan(pending_[i], i, out);
  }
  if (over || pending_.size() - begin_ > max_bytes_) {
    spent_ = true;
    dropRemainder();
    return false;
  }
  pending_.erase(0, begin_);
  begin_ = 0;
  // A large message leaves a large buffer behind: give it back once most
  // of it is unused, so that idle connections hold little memory.
  if (pending_.capacity() > kKeptCapacity && 4 * pending_.size() < pending_.capacity())
    pending_.shrink_to_fit();
  return true;
}

std::size_t MessageFramer::skipPlain(std::size_t i) const {
  // Bytes that cannot end the message or change its nesting are skipped
  // without the state machine: the bulk of a long string or scalar.
  const char* text = pending_.data();
  const std::size_t end = pending_.size();
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

void MessageFramer::scan(char c, std::size_t at, std::vector<std::string>& out) {
  if (c == '\n') {
    const bool blank = !started_;
    if (blank && after_text_) {
      begin_ = at + 1;  // only whitespace followed a complete text
    } else {
      emit(blank ? begin_ : at, out);
      begin_ = at + 1;
    }
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
    emit(at + 1, out);
    begin_ = at + 1;
    started_ = structured_ = false;
    after_text_ = true;
  }
}

void MessageFramer::emit(std::size_t end, std::vector<std::string>& out) {
  out.emplace_back(pending_, begin_, end - begin_);
}

std::string MessageFramer::takeRemainder() {
  std::string rest = started_ ? pending_.substr(begin_) : std::string();
  dropRemainder();
  return rest;
}

void MessageFramer::dropRemainder() {
  pending_.clear();
  pending_.shrink_to_fit();
  begin_ = 0;
  started_ = structured_ = after_text_ = false;
}

}  // namespace hfts::service
