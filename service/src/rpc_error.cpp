#include "service/rpc_error.h"

namespace hfts::service {

void throwInvalidParam(const std::string& field, const std::string& problem) {
  throw RpcError(ErrorCode::kInvalidParams, field + ": " + problem, field);
}

RpcError invalidParamFromPlanner(const std::string& message) {
  std::string field, problem;
  if (!message.empty() && message[0] == '\'') {  // 'field' problem
    const std::size_t close = message.find('\'', 1);
    field = message.substr(1, close - 1);
    problem = close == std::string::npos ? "" : message.substr(close + 1);
  } else if (const std::size_t colon = message.find(": "); colon != std::string::npos) {
    field = message.substr(0, colon);  // field: problem
    problem = message.substr(colon + 2);
    const std::size_t name = problem.find("for '");
    if (field == "parameters" && name != std::string::npos)
      field += "." + problem.substr(name + 5, problem.find('\'', name + 5) - name - 5);
  } else {
    return RpcError(ErrorCode::kInvalidParams, message);
  }
  problem.erase(0, problem.find_first_not_of(' '));
  return RpcError(ErrorCode::kInvalidParams, field + ": " + problem, field);
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
  }
  return "unknown";
}

}  // namespace hfts::service
