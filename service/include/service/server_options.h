#pragma once
// What hfts-server is started with (Server, server.h): where the catalog
// comes from, the address and port, the workers, the queue and the limits.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>

#include "service/planning_catalog.h"

namespace hfts::service {

struct ServerOptions {
  CatalogSources sources;                  ///< robot, databases, scenes (reload re-reads them)
  std::string bind_address = "127.0.0.1";  ///< IPv4 or IPv6 address to listen on
  std::uint16_t port = 0;                  ///< 0: an ephemeral port (see Server::port())
  int workers = 0;                         ///< planning threads; 0: one per hardware thread
  std::size_t queue_capacity = 64;         ///< plans waiting for a worker; more are "busy"
  /// Plans one client (a token, or a connection on a server without
  /// tokens) may have queued or running at once; more are "busy". 0: no cap.
  std::size_t max_plans_per_client = 16;
  double max_time_limit = 60.0;               ///< s; caps (and defaults) a plan's time_limit
  std::size_t max_message_bytes = 16u << 20;  ///< one message; larger closes the connection
  std::size_t max_connections = 256;          ///< open at once; one more is refused
  /// Server-wide bytes of unfinished messages beyond 64 KiB per connection;
  /// a connection whose message does not fit is refused and closed.
  std::size_t max_buffered_bytes = std::size_t{512} << 20;
  double read_timeout = 30.0;   ///< s to finish a begun message; 0: none
  double idle_timeout = 300.0;  ///< s of silence with no call pending; 0: none
  bool handle_signals = true;   ///< SIGINT/SIGTERM shut down gracefully; SIGHUP re-reads tokens
  /// The token file (access_tokens.h; docs/security.md); empty: no
  /// authentication, allowed only on a loopback address unless `insecure`.
  std::filesystem::path auth_tokens;
  /// Listen on a non-loopback address without tokens anyway.
  bool insecure = false;
  /// TLS (both or neither): the PEM certificate chain and private key;
  /// empty: plain TCP.
  std::filesystem::path tls_cert, tls_key;
  std::ostream* log = nullptr;  ///< one line per request; nullptr: no log
};

}  // namespace hfts::service
