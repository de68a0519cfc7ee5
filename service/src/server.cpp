#include "service/server.h"

#include <asio/io_context.hpp>
#include <asio/ip/tcp.hpp>
#include <asio/post.hpp>
#include <asio/signal_set.hpp>
#include <asio/steady_timer.hpp>

#include <asio/write.hpp>

#include <array>
#include <cmath>
#include <csignal>
#include <stdexcept>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "byte_stream.h"
#include "connection.h"
#include "method_dispatcher.h"

namespace hfts::service {

using asio::ip::tcp;

namespace {

constexpr auto kShutdownPoll = std::chrono::milliseconds(10);
constexpr auto kAcceptRetry = std::chrono::milliseconds(100);
constexpr int kAcceptBatch = 256;  // connections taken at once besides the accepted one
constexpr int kMaxLingering = 64;  // refused connections drained at once
constexpr auto kRefusedLinger = std::chrono::seconds(1);  // how long one is drained at most
constexpr auto kTrimDelay = std::chrono::milliseconds(200);

std::chrono::milliseconds timeoutOf(double seconds, const char* name) {
  if (!std::isfinite(seconds) || seconds < 0.0 || seconds > 1e6)
    throw std::invalid_argument(std::string("the ") + name +
                                " must be a number of seconds in [0, 1e6] (0: none)");
  return std::chrono::milliseconds(static_cast<std::int64_t>(std::llround(seconds * 1000.0)));
}

ConnectionLimits limitsOf(const ServerOptions& options) {
  if (options.max_message_bytes < 1024)
    throw std::invalid_argument("the message size limit must be at least 1024 bytes");
  if (options.max_connections < 1)
    throw std::invalid_argument("the connection limit must be at least 1");
  if (options.max_buffered_bytes < (std::size_t{1} << 20))
    throw std::invalid_argument("the input budget must be at least 1 MiB");
  ConnectionLimits limits;
  limits.max_message_bytes = options.max_message_bytes;
  limits.read_timeout = timeoutOf(options.read_timeout, "read timeout");
  limits.idle_timeout = timeoutOf(options.idle_timeout, "idle timeout");
  return limits;
}

tcp::endpoint endpointOf(const ServerOptions& options) {
  asio::error_code ec;
  const asio::ip::address address = asio::ip::make_address(options.bind_address, ec);
  if (ec)
    throw std::invalid_argument("bind address '" + options.bind_address +
                                "' is not an IPv4 or IPv6 address");
  return {address, options.port};
}

/// The TLS context of options.tls_cert and tls_key; nullopt for plain TCP.
std::optional<asio::ssl::context> tlsOf(const ServerOptions& options) {
  if (options.tls_cert.empty() != options.tls_key.empty())
    throw std::invalid_argument("TLS needs both a certificate (--tls-cert) and a key (--tls-key)");
  if (options.tls_cert.empty()) return std::nullopt;
  return serverTlsContext(options.tls_cert.string(), options.tls_key.string());
}

bool isLoopback(const asio::ip::address& a) {
  if (a.is_v6() && a.to_v6().is_v4_mapped())
    return asio::ip::make_address_v4(asio::ip::v4_mapped, a.to_v6()).is_loopback();
  return a.is_loopback();
}

/// The tokens of options.auth_tokens (null: none). Without tokens the
/// server listens only on a loopback address, unless options.insecure.
std::shared_ptr<const TokenTable> tokensOf(const ServerOptions& options) {
  if (!options.auth_tokens.empty())
    return std::make_shared<const TokenTable>(TokenTable::load(options.auth_tokens));
  if (!options.insecure && !isLoopback(endpointOf(options).address()))
    throw std::invalid_argument(
        "listening on " + options.bind_address +
        " without tokens would let anyone who reaches the port plan, reload and shut the "
        "server down: give --auth-tokens FILE (docs/security.md), or --insecure to do it anyway");
  return nullptr;
}

}  // namespace

class Server::Impl {
 public:
  Impl(ServerOptions options, std::shared_ptr<const PlanningCatalog> catalog)
      : options_(std::move(options)),
        initial_(catalog),
        dispatcher_(
            options_, std::move(catalog), tokensOf(options_),
            [this](std::function<void()> f) { asio::post(io_, std::move(f)); },
            [this](std::chrono::milliseconds delay, std::function<void()> f) {
              auto timer = std::make_shared<asio::steady_timer>(io_, delay);
              timer->async_wait([timer, f = std::move(f)](const asio::error_code&) { f(); });
            },
            [this] { beginShutdown("shutdown requested"); }),
        acceptor_(io_),
        signals_(io_),
        timer_(io_),
        trim_timer_(io_),
        log_(options_.log),
        tls_(tlsOf(options_)),
        limits_(limitsOf(options_)),
        budget_(options_.max_buffered_bytes) {
    listen(endpointOf(options_));
    dispatcher_.setConnectionLoad([this] {
      prune();
      return ConnectionLoad{connections_.size(), budget_.used()};
    });
    log_.captureOmplMessages();
    if (options_.handle_signals) {
      signals_.add(SIGINT);
      signals_.add(SIGTERM);
      if (!options_.auth_tokens.empty()) signals_.add(SIGHUP);
      waitForSignal();
    }
  }

  std::uint16_t port() const { return acceptor_.local_endpoint().port(); }
  int workers() const { return dispatcher_.workers(); }
  const PlanningCatalog& initialCatalog() const { return *initial_; }

  void run() {
    log_.event("listening on " + options_.bind_address + ":" + std::to_string(port()) +
               (tls_ ? " (TLS)" : "") + " with " + std::to_string(workers()) + " workers");
    accept();
    io_.run();
    log_.event("stopped");
  }

  void stop() {
    asio::post(io_, [this] { beginShutdown("stop requested"); });
  }

 private:
  void listen(const tcp::endpoint& endpoint) {
    asio::error_code ec;
    acceptor_.open(endpoint.protocol(), ec);
    if (!ec) acceptor_.set_option(tcp::acceptor::reuse_address(true), ec);
    if (!ec) acceptor_.bind(endpoint, ec);
    if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
    if (!ec) acceptor_.non_blocking(true, ec);
    if (ec)
      throw std::runtime_error("cannot listen on " + options_.bind_address + ":" +
                               std::to_string(endpoint.port()) + ": " + ec.message());
  }

  void accept() {
    acceptor_.async_accept([this](const asio::error_code& error, tcp::socket socket) {
      if (stopping_ || error == asio::error::operation_aborted) return;
      if (error) {  // e.g. out of file descriptors: wait a little, then accept again
        log_.event("accept failed: " + error.message());
        timer_.expires_after(kAcceptRetry);
        timer_.async_wait([this](const asio::error_code& e) {
          if (!e) accept();
        });
        return;
      }
      prune();
      admit(std::move(socket));
      // Take every connection already waiting, not one per trip through
      // the event loop: under a flood of busy connections a new client
      // would otherwise wait a full round of their reads per connection
      // ahead of it (docs/reliability.md).
      for (int n = 0; n < kAcceptBatch; ++n) {
        tcp::socket next(io_);
        asio::error_code ec;
        acceptor_.accept(next, ec);  // the acceptor is non-blocking
        if (ec) break;
        admit(std::move(next));
      }
      accept();
    });
  }

  /// Serves a new connection, or refuses it over the cap or the budget
  /// (connections_ pruned by the caller).
  void admit(tcp::socket socket) {
    if (connections_.size() >= options_.max_connections) {
      refuse(std::move(socket), ErrorCode::kTooManyConnections,
             "too many connections: the server has " + std::to_string(options_.max_connections) +
                 " open; try again later");
    } else if (!budget_.reserve(Connection::reservedBytes(limits_))) {
      refuse(std::move(socket), ErrorCode::kInputBudgetExhausted,
             "the server's input buffers are full; try again later");
    } else {
      auto connection =
          std::make_shared<Connection>(std::move(socket), tls_ ? &*tls_ : nullptr, dispatcher_,
                                       limits_, budget_, [this] { trimSoon(); });
      connections_.push_back(connection);
      connection->start();
    }
  }

  /// A connection not served: an error line, then the socket is closed.
  /// What the client sent meanwhile is read and dropped for up to a second
  /// (for at most kMaxLingering such connections at once), so that it reads
  /// the error instead of a reset.
  void refuse(tcp::socket socket, ErrorCode code, const std::string& message) {
    ++refused_;
    if (refused_ == 1 || refused_ % 1000 == 0)
      log_.event("refused a connection (" + message + "; " + std::to_string(refused_) +
                 " refused so far)");
    if (tls_) {  // the error line would need a handshake first: closed at once
      asio::error_code ignored;
      socket.close(ignored);
      return;
    }
    auto s = std::make_shared<tcp::socket>(std::move(socket));
    auto line =
        std::make_shared<std::string>(serialize(errorResponse(nullptr, RpcError(code, message))));
    asio::async_write(*s, asio::buffer(*line),
                      [this, s, line](const asio::error_code& error, std::size_t) {
                        asio::error_code ec;
                        if (error || lingering_ >= kMaxLingering) {
                          s->close(ec);
                          return;
                        }
                        s->shutdown(tcp::socket::shutdown_send, ec);
                        ++lingering_;
                        auto timer = std::make_shared<asio::steady_timer>(io_, kRefusedLinger);
                        timer->async_wait([s](const asio::error_code&) {
                          asio::error_code ignored;
                          s->close(ignored);
                        });
                        drainRefused(s, timer);
                      });
  }

  void drainRefused(const std::shared_ptr<tcp::socket>& s,
                    const std::shared_ptr<asio::steady_timer>& timer) {
    s->async_read_some(asio::buffer(discard_),
                       [this, s, timer](const asio::error_code& error, std::size_t) {
                         if (!error) return drainRefused(s, timer);
                         --lingering_;  // end of input, or closed by the timer
                         timer->cancel();
                       });
  }

  /// After large messages are freed, returns the free memory to the system
  /// once (glibc keeps freed heap memory otherwise; docs/reliability.md).
  void trimSoon() {
    if (trim_pending_) return;
    trim_pending_ = true;
    trim_timer_.expires_after(kTrimDelay);
    trim_timer_.async_wait([this](const asio::error_code&) {
      trim_pending_ = false;
#if defined(__GLIBC__)
      malloc_trim(0);
#endif
    });
  }

  void prune() {
    std::vector<std::weak_ptr<Connection>> open;
    for (const auto& weak : connections_)
      if (const auto c = weak.lock(); c && c->isOpen()) open.push_back(weak);
    connections_.swap(open);
  }

  /// Stops accepting, cancels every plan, lets the connections send their
  /// replies and close; run() returns when all are closed.
  void beginShutdown(const std::string& why) {
    if (stopping_) return;
    stopping_ = true;
    log_.event("shutting down (" + why + ")");
    asio::error_code ec;
    acceptor_.close(ec);
    timer_.cancel();
    trim_timer_.cancel();
    dispatcher_.stop();
    for (const auto& weak : connections_)
      if (const auto c = weak.lock()) c->finish();
    waitForConnections();
  }

  void waitForSignal() {
    signals_.async_wait([this](const asio::error_code& error, int signal) {
      if (error) return;
      if (signal != SIGHUP) return beginShutdown("signal " + std::to_string(signal));
      rereadTokens();
      waitForSignal();
    });
  }

  /// SIGHUP: the token file again. A file that does not load leaves the
  /// old tokens in force.
  void rereadTokens() {
    try {
      auto tokens = std::make_shared<const TokenTable>(TokenTable::load(options_.auth_tokens));
      log_.event("token file re-read: " + std::to_string(tokens->size()) + " tokens");
      dispatcher_.setTokens(std::move(tokens));
    } catch (const std::exception& e) {
      log_.event(std::string("token file not re-read, the old tokens stay in force: ") + e.what());
    }
  }

  void waitForConnections() {
    prune();
    if (connections_.empty() && dispatcher_.idle()) {
      signals_.cancel();
      return;  // nothing is left to run: io_.run() returns
    }
    timer_.expires_after(kShutdownPoll);
    timer_.async_wait([this](const asio::error_code&) { waitForConnections(); });
  }

  ServerOptions options_;
  asio::io_context io_{1};
  std::shared_ptr<const PlanningCatalog> initial_;
  MethodDispatcher dispatcher_;  // after io_: its threads post to io_ until joined
  tcp::acceptor acceptor_;
  asio::signal_set signals_;
  asio::steady_timer timer_;
  asio::steady_timer trim_timer_;
  RequestLog log_;
  std::optional<asio::ssl::context> tls_;
  ConnectionLimits limits_;
  InputBudget budget_;
  std::vector<std::weak_ptr<Connection>> connections_;
  std::size_t refused_ = 0;
  int lingering_ = 0;                 // refused connections being drained
  std::array<char, 4096> discard_{};  // what they send, dropped
  bool trim_pending_ = false;
  bool stopping_ = false;
};

// The access options are checked before the catalog loads (which takes
// seconds): a bad token file or an unguarded address fails at once.
Server::Server(ServerOptions options)
    : Server(options, (tokensOf(options), tlsOf(options), PlanningCatalog::load(options.sources))) {
}

Server::Server(ServerOptions options, std::shared_ptr<const PlanningCatalog> catalog)
    : impl_(std::make_unique<Impl>(std::move(options), std::move(catalog))) {}

Server::~Server() = default;

std::uint16_t Server::port() const {
  return impl_->port();
}
int Server::workers() const {
  return impl_->workers();
}
const PlanningCatalog& Server::initialCatalog() const {
  return impl_->initialCatalog();
}
void Server::run() {
  impl_->run();
}
void Server::stop() {
  impl_->stop();
}

}  // namespace hfts::service
