#include "service/rpc_error.h"

namespace hfts::service {

void throwInvalidParam(const std::string& field, const std::string& problem) {
  throw RpcError(ErrorCode::kInvalidParams, field + ": " + problem, field);
}

RpcError invalidParam(const InvalidArgument& error, const std::string& prefix) {
  const std::string field = prefix + error.field();
  return RpcError(ErrorCode::kInvalidParams, field + ": " + error.problem(), field);
}

const char* toString(ErrorCode code) {
  switch (code) {
    case ErrorCode::kParseError:
      return "parse_error";
    case ErrorCode::kInvalidRequest:
      return "invalid_request";
    case ErrorCode::kMethodNotFound:
      return "method_not_found";
    case ErrorCode::kInvalidParams:
      return "invalid_params";
    case ErrorCode::kInternalError:
      return "internal_error";
    case ErrorCode::kBusy:
      return "busy";
    case ErrorCode::kShuttingDown:
      return "shutting_down";
    case ErrorCode::kForbidden:
      return "forbidden";
    case ErrorCode::kMessageTooLarge:
      return "message_too_large";
    case ErrorCode::kReloadFailed:
      return "reload_failed";
    case ErrorCode::kTooManyConnections:
      return "too_many_connections";
    case ErrorCode::kInputBudgetExhausted:
      return "input_budget_exhausted";
    case ErrorCode::kTimedOut:
      return "timed_out";
    case ErrorCode::kUnauthorized:
      return "unauthorized";
  }
  return "unknown";
}

}  // namespace hfts::service
