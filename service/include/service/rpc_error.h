#pragma once
// The error codes of the planning service (docs/protocol.md): the JSON-RPC
// 2.0 codes and the service's own application codes, and the exception that
// carries one from a method to the reply.

#include <stdexcept>
#include <string>

#include "core/invalid_argument.h"

namespace hfts::service {

/// JSON-RPC 2.0 error codes (-32700 .. -32600) and the application codes of
/// the service (the implementation-defined range -32099 .. -32000).
enum class ErrorCode : int {
  kParseError = -32700,      ///< not valid JSON (also: an empty line)
  kInvalidRequest = -32600,  ///< valid JSON but not a JSON-RPC 2.0 request
  kMethodNotFound = -32601,
  kInvalidParams = -32602,  ///< the message names the offending field
  kInternalError = -32603,
  kBusy = -32001,                ///< a queue (plans, grasp.quality) is full; try again later
  kShuttingDown = -32002,        ///< the server is stopping and takes no new work
  kForbidden = -32003,           ///< the connection's role may not call the method
  kMessageTooLarge = -32004,     ///< over the size limit; the connection is closed
  kReloadFailed = -32005,        ///< reload could not read the robot, map or scenes
  kTooManyConnections = -32006,  ///< at the connection cap: sent, then the connection is closed
  kInputBudgetExhausted =
      -32007,          ///< the server's input buffers are full; the connection is closed
  kTimedOut = -32008,  ///< a message not finished in time, or a silent connection; closed
  kUnauthorized =
      -32009,  ///< no valid token yet (docs/security.md); a failed auth closes the connection
};

/// Thrown by method handlers; becomes the reply's "error" member.
/// `field` (may be empty) names the offending parameter, e.g.
/// "object_pose.orientation"; it is also part of the message.
class RpcError : public std::runtime_error {
 public:
  RpcError(ErrorCode code, const std::string& message, std::string field = {})
      : std::runtime_error(message), code_(code), field_(std::move(field)) {}

  ErrorCode code() const { return code_; }
  const std::string& field() const { return field_; }

 private:
  ErrorCode code_;
  std::string field_;
};

/// Snake-case name of a code, for log lines ("invalid_params", "busy").
const char* toString(ErrorCode code);

/// Throws RpcError(kInvalidParams) with the message "<field>: <problem>".
[[noreturn]] void throwInvalidParam(const std::string& field, const std::string& problem);

/// A library's InvalidArgument as RpcError(kInvalidParams) with its field:
/// the message stays "<field>: <problem>". `prefix` (e.g. "scene.") is put
/// before the field when the library's request is part of a larger one.
RpcError invalidParam(const InvalidArgument& error, const std::string& prefix = {});

}  // namespace hfts::service
