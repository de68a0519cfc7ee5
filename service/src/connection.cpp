#include "connection.h"

#include <asio/write.hpp>

namespace hfts::service {

using asio::ip::tcp;
using nlohmann::json;

namespace {

constexpr std::size_t kMaxUnsentBytes = 64u << 20;  // stop reading while this much is unsent
constexpr auto kLinger = std::chrono::seconds(2);

}  // namespace

Connection::Connection(tcp::socket socket, asio::ssl::context* tls, MethodDispatcher& dispatcher,
                       const ConnectionLimits& limits, InputBudget& budget,
                       std::function<void()> onLargeBufferFreed)
    : stream_(std::move(socket), tls),
      dispatcher_(dispatcher),
      limits_(limits),
      budget_(budget),
      on_large_buffer_freed_(std::move(onLargeBufferFreed)),
      framer_(limits.max_message_bytes),
      charged_(reservedBytes(limits)),
      last_activity_(std::chrono::steady_clock::now()),
      linger_timer_(stream_.socket().get_executor()),
      deadline_timer_(stream_.socket().get_executor()) {
  asio::error_code ec;
  const tcp::endpoint remote = stream_.socket().remote_endpoint(ec);
  if (ec) {
    caller_.peer = "unknown";
  } else {
    const std::string address = remote.address().to_string();
    caller_.peer = (remote.address().is_v6() ? "[" + address + "]" : address) + ":" +
                   std::to_string(remote.port());
    caller_.address = address;
  }
  caller_.plans = std::make_shared<CancelRegistry>();
  // Replies are small: do not wait to fill a segment.
  stream_.socket().set_option(tcp::no_delay(true), ec);
}

void Connection::start() {
  armDeadline();
  stream_.handshake([self = shared_from_this()](const asio::error_code& error) {
    if (self->closed_) return;
    if (error) return self->close();  // no TLS: nothing can be said to the peer
    self->handshaking_ = false;
    self->last_activity_ = std::chrono::steady_clock::now();
    self->readMore();
    self->armDeadline();
  });
}

void Connection::finish() {
  input_done_ = true;
  if (handshaking_) return close();
  closeWhenDone();
}

void Connection::readMore() {
  if (handshaking_ || reading_ || input_done_ || closed_ || outbox_bytes_ > kMaxUnsentBytes) return;
  reading_ = true;
  stream_.readSome(asio::buffer(buffer_),
                   [self = shared_from_this()](const asio::error_code& error, std::size_t bytes) {
                     self->reading_ = false;
                     self->onRead(error, bytes);
                   });
}

void Connection::onRead(const asio::error_code& error, std::size_t bytes) {
  if (closed_) return;
  if (draining_) {  // the read was in flight when the draining began
    if (error) return close();
    return drainMore();
  }
  if (input_done_) {  // shutting down: what arrives now is not served
    closeWhenDone();
    return;
  }
  if (error) {
    if (framer_.inUnclosedText()) {  // not worth parsing: it may be megabytes
      const std::size_t unclosed = framer_.kept();
      framer_.dropRemainder();
      sendInputError(ErrorCode::kParseError, "parse error: the input ended inside a JSON text (" +
                                                 std::to_string(unclosed) + " bytes not closed)");
    } else if (const std::string rest = framer_.takeRemainder(); !rest.empty()) {
      handleMessage(rest);  // a last text without newline
    }
    endInput(/*cancelPlans=*/true);
    return;
  }
  const auto now = std::chrono::steady_clock::now();
  last_activity_ = now;
  const bool wasInMessage = framer_.inMessage();
  std::vector<std::string> messages;
  const bool withinLimit = framer_.feed({buffer_.data(), bytes}, messages);
  // The read timeout counts from the first byte of the unfinished message
  // (at best known to within this read).
  if (framer_.inMessage() && (!wasInMessage || !messages.empty())) message_began_ = now;
  for (const std::string& text : messages) handleMessage(text);
  if (!withinLimit) {
    refuseAndClose(ErrorCode::kMessageTooLarge, "message too large: over the limit of " +
                                                    std::to_string(framer_.maxMessageBytes()) +
                                                    " bytes; closing the connection");
    return;
  }
  if (!chargeInput()) {
    refuseAndClose(ErrorCode::kInputBudgetExhausted,
                   "the server's input buffers are full (" +
                       std::to_string(budget_.capacity() >> 20) +
                       " MiB across connections); closing the connection");
    return;
  }
  armDeadline();
  readMore();
}

std::size_t Connection::reservedBytes(const ConnectionLimits& limits) {
  return sizeof(buffer_) + limits.free_input_bytes;
}

bool Connection::chargeInput() {
  const std::size_t buffered = framer_.buffered();
  std::size_t wanted = closed_ ? 0 : reservedBytes(limits_);
  if (buffered > limits_.free_input_bytes) {
    wanted += buffered - limits_.free_input_bytes;
    held_large_input_ = true;
  }
  if (wanted <= charged_) {
    budget_.give(charged_ - wanted);
    charged_ = wanted;
    return true;
  }
  if (!budget_.draw(wanted - charged_)) return false;
  charged_ = wanted;
  return true;
}

void Connection::sendInputError(ErrorCode code, const std::string& message) {
  const json response = errorResponse(nullptr, RpcError(code, message));
  dispatcher_.logRejected(caller_, response);
  send(response);
}

void Connection::refuseAndClose(ErrorCode code, const std::string& message) {
  framer_.dropRemainder();
  chargeInput();  // gives its bytes back
  sendInputError(code, message);
  linger_ = true;
  endInput(/*cancelPlans=*/true);
}

std::optional<std::chrono::steady_clock::time_point> Connection::deadline() const {
  if (handshaking_) {
    if (limits_.read_timeout.count() == 0) return std::nullopt;
    return last_activity_ + limits_.read_timeout;
  }
  if (framer_.inMessage()) {
    if (limits_.read_timeout.count() == 0) return std::nullopt;
    return message_began_ + limits_.read_timeout;
  }
  // A client waiting for a plan's reply is not idle.
  if (outstanding_ > 0 || writing_ || !outbox_.empty() || limits_.idle_timeout.count() == 0)
    return std::nullopt;
  return last_activity_ + limits_.idle_timeout;
}

void Connection::armDeadline() {
  if (closed_ || input_done_) {
    deadline_timer_.cancel();
    armed_.reset();
    return;
  }
  // A pending wait that ends no later looks again when it fires (onDeadline),
  // so a read that only moves the deadline later costs no timer operation.
  const auto when = deadline();
  if (!when || (armed_ && *armed_ <= *when)) return;
  armed_ = when;
  deadline_timer_.expires_at(*when);  // a wait pending for later ends as aborted
  deadline_timer_.async_wait([self = shared_from_this()](const asio::error_code& error) {
    if (error) return;
    self->armed_.reset();
    self->onDeadline();
  });
}

void Connection::onDeadline() {
  if (closed_ || input_done_) return;
  const auto when = deadline();
  if (!when) return;
  if (std::chrono::steady_clock::now() < *when) {
    armDeadline();
    return;
  }
  if (handshaking_) return close();  // a TLS handshake not finished in time
  const auto seconds = [](std::chrono::milliseconds t) {
    return t.count() % 1000 == 0 ? std::to_string(t.count() / 1000) + " s"
                                 : std::to_string(t.count()) + " ms";
  };
  if (framer_.inMessage())
    refuseAndClose(ErrorCode::kTimedOut, "message not finished within the read timeout of " +
                                             seconds(limits_.read_timeout) +
                                             "; closing the connection");
  else
    refuseAndClose(ErrorCode::kTimedOut, "no request within the idle timeout of " +
                                             seconds(limits_.idle_timeout) +
                                             "; closing the connection");
}

Responder Connection::responder(std::function<void(json)> deliver) {
  ++outstanding_;
  return [self = shared_from_this(), deliver = std::move(deliver)](json response) {
    deliver(std::move(response));
    --self->outstanding_;
    if (self->caller_.session->close_after_reply && !self->input_done_) {
      // A failed auth: nothing more is read; the reply goes out, the rest
      // of the input is drained for a moment, then the socket closes.
      self->linger_ = true;
      self->endInput(/*cancelPlans=*/true);
      return;
    }
    self->last_activity_ = std::chrono::steady_clock::now();
    self->closeWhenDone();
    self->armDeadline();
  };
}

void Connection::handleMessage(const std::string& text) {
  Message message = parseMessage(text);
  for (const MessageItem& item : message.items)
    if (!item.call) dispatcher_.logRejected(caller_, item.error);
  if (!message.batch) {
    MessageItem& item = message.items.front();
    if (!item.call)
      send(item.error);
    else
      dispatcher_.dispatch(*item.call, caller_, responder([this](json r) { send(r); }));
    return;
  }
  // A batch is answered with one array once all its calls are answered.
  struct Batch {
    json responses = json::array();
    std::size_t pending = 0;
  };
  auto batch = std::make_shared<Batch>();
  for (const MessageItem& item : message.items) {
    if (item.call)
      ++batch->pending;
    else
      batch->responses.push_back(item.error);
  }
  if (batch->pending == 0) send(batch->responses);
  for (const MessageItem& item : message.items) {
    if (!item.call) continue;
    dispatcher_.dispatch(*item.call, caller_, responder([this, batch](json r) {
      if (!r.is_null()) batch->responses.push_back(std::move(r));
      if (--batch->pending == 0 && !batch->responses.empty()) send(batch->responses);
    }));
  }
}

void Connection::send(const json& response) {
  if (closed_ || response.is_null()) return;
  outbox_.push_back(serialize(response));
  outbox_bytes_ += outbox_.back().size();
  writeMore();
}

void Connection::writeMore() {
  if (writing_ || outbox_.empty() || closed_) return;
  writing_ = true;
  in_flight_.assign(std::make_move_iterator(outbox_.begin()),
                    std::make_move_iterator(outbox_.end()));
  outbox_.clear();
  std::vector<asio::const_buffer> buffers;
  for (const std::string& line : in_flight_) buffers.push_back(asio::buffer(line));
  stream_.write(buffers,
                [self = shared_from_this()](const asio::error_code& error, std::size_t bytes) {
                  self->writing_ = false;
                  self->outbox_bytes_ -= bytes;
                  self->in_flight_.clear();
                  if (error) {  // the peer is gone
                    self->caller_.plans->cancelAll();
                    self->input_done_ = true;
                    self->close();
                    return;
                  }
                  self->last_activity_ = std::chrono::steady_clock::now();
                  self->writeMore();
                  self->readMore();
                  self->closeWhenDone();
                  self->armDeadline();
                });
}

void Connection::endInput(bool cancelPlans) {
  input_done_ = true;
  if (cancelPlans) caller_.plans->cancelAll();
  closeWhenDone();
}

void Connection::closeWhenDone() {
  if (closed_ || !input_done_ || outstanding_ > 0 || writing_ || !outbox_.empty()) return;
  if (linger_)
    drainThenClose();
  else
    close();
}

void Connection::drainThenClose() {
  linger_ = false;
  draining_ = true;
  stream_.shutdownSend();
  linger_timer_.expires_after(kLinger);
  linger_timer_.async_wait([self = shared_from_this()](const asio::error_code& error) {
    if (!error) self->close();
  });
  drainMore();
}

void Connection::drainMore() {
  // One read at a time: a read still in flight (a timeout closed the
  // connection while it waited) goes on draining when it completes
  // (onRead). A second read on the same stream would be two TLS reads at
  // once, which corrupt memory.
  if (reading_ || closed_) return;
  reading_ = true;
  stream_.readSome(asio::buffer(buffer_),
                   [self = shared_from_this()](const asio::error_code& error, std::size_t) {
                     self->reading_ = false;
                     if (error || self->closed_) return self->close();
                     self->drainMore();
                   });
}

void Connection::close() {
  if (closed_) return;
  closed_ = true;
  linger_timer_.cancel();
  deadline_timer_.cancel();
  stream_.close();
  outbox_.clear();
  outbox_.shrink_to_fit();
  outbox_bytes_ = 0;
  framer_.dropRemainder();
  chargeInput();
  if (held_large_input_ && on_large_buffer_freed_) on_large_buffer_freed_();
}

}  // namespace hfts::service
