#pragma once
// hfts-server: the planning service. Serves the methods of docs/protocol.md
// (JSON-RPC 2.0, one message per line, over plain TCP) with a pool of
// planning threads. Asio and JSON stay behind this header.

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "service/planning_catalog.h"

namespace hfts::service {

struct ServerOptions {
  CatalogSources sources;                     ///< robot, databases, scenes (reload re-reads them)
  std::string bind_address = "127.0.0.1";     ///< IPv4 or IPv6 address to listen on
  std::uint16_t port = 0;                     ///< 0: an ephemeral port (see Server::port())
  int workers = 0;                            ///< planning threads; 0: one per hardware thread
  std::size_t queue_capacity = 64;            ///< plans waiting for a worker; more are "busy"
  double max_time_limit = 60.0;               ///< s; caps (and defaults) a plan's time_limit
  std::size_t max_message_bytes = 16u << 20;  ///< one message; larger closes the connection
  std::size_t max_connections = 256;          ///< open at once; one more is refused
  /// Server-wide bytes of unfinished messages beyond 64 KiB per connection;
  /// a connection whose message does not fit is refused and closed.
  std::size_t max_buffered_bytes = std::size_t{512} << 20;
  double read_timeout = 30.0;   ///< s to finish a begun message; 0: none
  double idle_timeout = 300.0;  ///< s of silence with no call pending; 0: none
  bool handle_signals = true;   ///< SIGINT/SIGTERM shut down gracefully
  std::ostream* log = nullptr;  ///< one line per request; nullptr: no log
};

/// The service. Construction loads the catalog and binds the socket; run()
/// serves until a `shutdown` call, a signal or stop(), then cancels the
/// running plans, sends every reply and returns.
class Server {
 public:
  /// Loads PlanningCatalog::load(options.sources). Throws
  /// std::runtime_error naming the file, or the address that cannot be
  /// bound, and std::invalid_argument for bad options.
  explicit Server(ServerOptions options);
  /// Serves an already loaded catalog (benchmarks, tests); reload still
  /// reads options.sources.
  Server(ServerOptions options, std::shared_ptr<const PlanningCatalog> catalog);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// The port actually bound (the ephemeral one when options.port is 0).
  std::uint16_t port() const;
  int workers() const;
  /// The catalog served at start (reload may replace it later).
  const PlanningCatalog& initialCatalog() const;

  /// Serves on the calling thread until the server has shut down.
  void run();
  /// Starts a graceful shutdown; callable from any thread.
  void stop();

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hfts::service
