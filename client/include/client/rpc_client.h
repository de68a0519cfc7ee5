#pragma once
// A blocking client of the planning service (docs/protocol.md): one TCP
// connection, one JSON-RPC 2.0 call at a time. Knows the protocol only,
// no planner code. Asio stays behind this header.

#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

namespace hfts::client {

/// The server answered with an error: its code (docs/protocol.md) and
/// message; `field` names the offending parameter when the server did.
class RpcCallError : public std::runtime_error {
 public:
  RpcCallError(int code, const std::string& message, std::string field)
      : std::runtime_error(message), code_(code), field_(std::move(field)) {}
  int code() const { return code_; }
  const std::string& field() const { return field_; }

 private:
  int code_;
  std::string field_;
};

/// The server could not be reached, closed the connection, or sent
/// something that is not a JSON-RPC response.
class ConnectionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What a client does when the connection fails before an answer arrived
/// (the server died, a balancer dropped it, nothing listens yet): connect
/// again and send the call again, after `backoff`, doubling up to 2 s. Every
/// method except `cancel` (whose id belongs to the lost connection) and
/// `shutdown` (which would reach another instance behind a balancer) is
/// safe to repeat: a plan is determined by its seed.
struct RetryPolicy {
  int retries = 2;       ///< further attempts after the first; 0: none
  double backoff = 0.2;  ///< seconds before the first retry
  /// Called before each retry with the failure and the attempt about to
  /// start (2, 3, ...), e.g. to tell the user; may be empty.
  std::function<void(const std::string& why, int attempt)> on_retry;
};

/// How the client reaches a server with tokens or TLS (docs/security.md).
struct Access {
  /// Sent with `auth` as the first call on every connection (again after a
  /// reconnection); empty: none (a server without tokens).
  std::string token;
  /// Speak TLS (TLS 1.2 or later). The server's certificate must verify
  /// against `ca_file` (PEM; empty: the system's CAs) and name the host.
  bool tls = false;
  std::string ca_file;
};

/// The token for a client from `tokenFile` (its first line, without
/// surrounding spaces) when given, else from the environment variable
/// HFTS_TOKEN, else empty. Throws std::runtime_error naming a file that
/// cannot be read or holds no token.
std::string tokenFrom(const std::string& tokenFile);

class RpcClient {
 public:
  /// Connects (with the policy's retries; with TLS, verifying the server's
  /// certificate) and authenticates when `access` has a token; throws
  /// ConnectionError naming host and port (and a certificate that does not
  /// verify), and RpcCallError (-32009) for a token the server does not
  /// accept.
  RpcClient(const std::string& host, std::uint16_t port, RetryPolicy retry = {},
            Access access = {});
  ~RpcClient();
  RpcClient(const RpcClient&) = delete;
  RpcClient& operator=(const RpcClient&) = delete;

  /// Sends {"jsonrpc": "2.0", "id": n, "method", "params"} and waits for
  /// the response with that id. Returns its result; throws RpcCallError
  /// for an error response and ConnectionError for a transport failure
  /// that outlasted the retries.
  nlohmann::json call(const std::string& method, const nlohmann::json& params);

  /// Connections made again after a failure, over this client's life.
  int reconnections() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hfts::client
