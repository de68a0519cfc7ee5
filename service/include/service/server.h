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

#include "service/server_options.h"

namespace hfts::service {

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
