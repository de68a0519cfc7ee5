#pragma once
// One client connection: reads messages, hands their calls to the
// dispatcher and writes the responses, in any order, as they complete.

#include <asio/ip/tcp.hpp>
#include <asio/steady_timer.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "byte_stream.h"
#include "method_dispatcher.h"
#include "service/message_framer.h"

namespace hfts::service {

/// The server-wide budget for buffered input: each connection's read buffer
/// and free allowance, and what unfinished messages hold beyond it. Long
/// messages leave a sixteenth of it (at most 32 MiB) to the reservations of
/// connections still to come, so that a normal client is served while the
/// budget is full of unfinished messages. Used only on the I/O thread.
class InputBudget {
 public:
  explicit InputBudget(std::size_t bytes)
      : capacity_(bytes), headroom_(std::min(bytes / 16, std::size_t{32} << 20)) {}
  /// A new connection's reservation: false (and nothing taken) when fewer
  /// than `bytes` are left.
  bool reserve(std::size_t bytes) { return take(bytes, 0); }
  /// More for an unfinished message: false (and nothing taken) unless the
  /// headroom stays free besides.
  bool draw(std::size_t bytes) { return take(bytes, headroom_); }
  void give(std::size_t bytes) { used_ -= bytes; }
  std::size_t used() const { return used_; }
  std::size_t capacity() const { return capacity_; }

 private:
  bool take(std::size_t bytes, std::size_t keepFree) {
    if (used_ + keepFree > capacity_ || bytes > capacity_ - used_ - keepFree) return false;
    used_ += bytes;
    return true;
  }

  std::size_t capacity_;
  std::size_t headroom_;
  std::size_t used_ = 0;
};

/// What one connection may hold and how long it may take.
struct ConnectionLimits {
  std::size_t max_message_bytes = 16u << 20;
  /// Bytes of an unfinished message a connection may buffer within what it
  /// reserved of the InputBudget when it opened: ordinary requests never
  /// wait for the budget.
  std::size_t free_input_bytes = 64u << 10;
  std::chrono::milliseconds read_timeout{0};  ///< to finish a begun message; 0: none
  std::chrono::milliseconds idle_timeout{0};  ///< silence with nothing pending; 0: none
};

/// Lives as long as its socket has an operation pending or a call has not
/// been answered. Used only on the I/O thread.
///
/// End of input (the peer closed or half-closed) counts as a disconnect:
/// the connection's plans are cancelled, their replies are still written
/// if the peer reads, then the socket is closed. A message over the size
/// limit gets an error, then the connection is closed after its input has
/// been drained for a moment (so that the peer sees the error, not a reset).
/// The same happens when the server's input budget cannot hold the rest of
/// a message, when a begun message is not finished within the read timeout,
/// and when the connection stays silent with nothing pending for the idle
/// timeout.
class Connection : public std::enable_shared_from_this<Connection> {
 public:
  /// `onLargeBufferFreed` runs (on the I/O thread) when the connection
  /// closes after it held a large message: the server then returns free
  /// memory to the system. The caller has taken reservedBytes() from
  /// `budget` for it; the connection gives them back when it closes.
  /// `tls` (may be null: plain TCP) must outlive the connection; a TLS
  /// handshake not done within the read timeout closes it.
  Connection(asio::ip::tcp::socket socket, asio::ssl::context* tls, MethodDispatcher& dispatcher,
             const ConnectionLimits& limits, InputBudget& budget,
             std::function<void()> onLargeBufferFreed);

  /// What an open connection holds of the budget before its messages grow
  /// beyond the free allowance: its read buffer and that allowance.
  static std::size_t reservedBytes(const ConnectionLimits& limits);

  void start();
  /// Server shutdown: read nothing more, close once every call received so
  /// far has been answered and the answers written.
  void finish();
  bool isOpen() const { return !closed_; }

 private:
  void readMore();
  void onRead(const asio::error_code& error, std::size_t bytes);
  void handleMessage(const std::string& text);
  /// A Responder for one call; counts it as outstanding until called.
  Responder responder(std::function<void(nlohmann::json)> deliver);
  void send(const nlohmann::json& response);
  void writeMore();
  /// Charges the framer's buffered bytes beyond the free allowance to the
  /// budget; false when the budget cannot hold them.
  bool chargeInput();
  /// Sends `error` (id null), drops the unfinished input and closes after
  /// draining, as for an oversized message.
  void refuseAndClose(ErrorCode code, const std::string& message);
  /// Logs and sends an error response (id null) to input that held no call.
  void sendInputError(ErrorCode code, const std::string& message);
  std::optional<std::chrono::steady_clock::time_point> deadline() const;
  void armDeadline();
  void onDeadline();
  void endInput(bool cancelPlans);
  void closeWhenDone();
  void drainThenClose();
  /// The next read of the draining (none while a read is in flight).
  void drainMore();
  void close();

  ByteStream stream_;
  MethodDispatcher& dispatcher_;
  ConnectionLimits limits_;
  InputBudget& budget_;
  std::function<void()> on_large_buffer_freed_;
  MessageFramer framer_;
  std::size_t charged_ = 0;        // bytes taken from budget_
  bool held_large_input_ = false;  // buffered more than the free allowance once
  std::chrono::steady_clock::time_point message_began_{};
  std::chrono::steady_clock::time_point last_activity_{};
  Caller caller_;
  std::array<char, 16 * 1024> buffer_{};
  std::deque<std::string> outbox_;
  std::vector<std::string> in_flight_;  // the strings of the write in progress
  std::size_t outbox_bytes_ = 0;
  std::size_t outstanding_ = 0;  // calls not answered yet
  bool handshaking_ = true;      // until the TLS handshake is done (plain TCP: start())
  bool reading_ = false;
  bool writing_ = false;
  bool input_done_ = false;
  bool linger_ = false;    // drain the input before closing (oversized message)
  bool draining_ = false;  // reading only to drop the input, until the close
  bool closed_ = false;
  asio::steady_timer linger_timer_;
  asio::steady_timer deadline_timer_;
  std::optional<std::chrono::steady_clock::time_point> armed_;  // when deadline_timer_ fires
};

}  // namespace hfts::service
