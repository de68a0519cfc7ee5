#pragma once
// One client connection: reads messages, hands their calls to the
// dispatcher and writes the responses, in any order, as they complete.

#include <asio/ip/tcp.hpp>
#include <asio/steady_timer.hpp>
#include <nlohmann/json.hpp>

#include <array>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "method_dispatcher.h"
#include "service/message_framer.h"

namespace hfts::service {

/// Lives as long as its socket has an operation pending or a call has not
/// been answered. Used only on the I/O thread.
///
/// End of input (the peer closed or half-closed) counts as a disconnect:
/// the connection's plans are cancelled, their replies are still written
/// if the peer reads, then the socket is closed. A message over the size
/// limit gets an error, then the connection is closed after its input has
/// been drained for a moment (so that the peer sees the error, not a reset).
class Connection : public std::enable_shared_from_this<Connection> {
 public:
  Connection(asio::ip::tcp::socket socket, MethodDispatcher& dispatcher,
             std::size_t maxMessageBytes);

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
  void rejectOversized();
  void endInput(bool cancelPlans);
  void closeWhenDone();
  void drainThenClose();
  void close();

  asio::ip::tcp::socket socket_;
  MethodDispatcher& dispatcher_;
  MessageFramer framer_;
  Caller caller_;
  std::array<char, 64 * 1024> buffer_{};
  std::deque<std::string> outbox_;
  std::vector<std::string> in_flight_;  // the strings of the write in progress
  std::size_t outbox_bytes_ = 0;
  std::size_t outstanding_ = 0;  // calls not answered yet
  bool reading_ = false;
  bool writing_ = false;
  bool input_done_ = false;
  bool linger_ = false;  // drain the input before closing (oversized message)
  bool closed_ = false;
  asio::steady_timer linger_timer_;
};

}  // namespace hfts::service
