#include "json_rpc.h"

#include <algorithm>

#include "service/json_nesting.h"

namespace hfts::service {
namespace {

using nlohmann::json;

int nestingDepth(std::string_view text) {
  JsonNesting nesting;
  int deepest = 0;
  for (const char c : text) deepest = std::max(deepest, nesting.consume(c));
  return deepest;
}

MessageItem invalid(const json& id, const std::string& problem) {
  return {std::nullopt,
          errorResponse(id, RpcError(ErrorCode::kInvalidRequest, "invalid request: " + problem))};
}

bool isValidId(const json& id) {
  return id.is_string() || id.is_number() || id.is_null();
}

MessageItem parseCall(const json& element) {
  if (!element.is_object()) return invalid(nullptr, "a request must be a JSON object");
  const auto idIt = element.find("id");
  const bool hasId = idIt != element.end();
  if (hasId && !isValidId(*idIt)) return invalid(nullptr, "'id' must be a string, number or null");
  const json id = hasId ? *idIt : json();
  for (const auto& member : element.items())
    if (member.key() != "jsonrpc" && member.key() != "method" && member.key() != "params" &&
        member.key() != "id")
      return invalid(id, "unknown member '" + member.key() + "'");
  const auto version = element.find("jsonrpc");
  if (version == element.end() || *version != "2.0")
    return invalid(id, "'jsonrpc' must be \"2.0\"");
  const auto method = element.find("method");
  if (method == element.end() || !method->is_string())
    return invalid(id, "'method' must be a string");
  Call call;
  call.id = id;
  call.notification = !hasId;
  call.method = method->get<std::string>();
  const auto params = element.find("params");
  if (params != element.end()) {
    if (!params->is_object() && !params->is_array())
      return invalid(id, "'params' must be an object or an array");
    call.params = *params;
  }
  return {std::move(call), json()};
}

MessageItem failure(ErrorCode code, const std::string& message) {
  return {std::nullopt, errorResponse(nullptr, RpcError(code, message))};
}

}  // namespace

Message parseMessage(std::string_view text) {
  Message message;
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
    message.items.push_back(failure(ErrorCode::kParseError, "parse error: empty line"));
    return message;
  }
  if (nestingDepth(text) > kMaxNestingDepth) {
    message.items.push_back(failure(
        ErrorCode::kInvalidRequest,
        "invalid request: nested deeper than " + std::to_string(kMaxNestingDepth) + " levels"));
    return message;
  }
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {  // parse_error, or out_of_range for 1e400
    const std::string what = e.what();  // "[json.exception.parse_error.101] parse error at ..."
    const std::size_t tag = what.find("] ");
    const std::string problem = tag == std::string::npos ? what : what.substr(tag + 2);
    message.items.push_back(failure(ErrorCode::kParseError, problem.rfind("parse error", 0) == 0
                                                                ? problem
                                                                : "parse error: " + problem));
    return message;
  }
  if (!root.is_array()) {
    message.items.push_back(parseCall(root));
    return message;
  }
  if (root.empty() || root.size() > kMaxBatchCalls) {
    message.items.push_back(
        failure(ErrorCode::kInvalidRequest, "invalid request: a batch must hold 1 to " +
                                                std::to_string(kMaxBatchCalls) + " requests, got " +
                                                std::to_string(root.size())));
    return message;
  }
  message.batch = true;
  for (const json& element : root) message.items.push_back(parseCall(element));
  return message;
}

json resultResponse(const json& id, json result) {
  return {{"jsonrpc", "2.0"}, {"id", id}, {"result", std::move(result)}};
}

json errorResponse(const json& id, const RpcError& error) {
  // Messages quote what the client sent (names, fields): keep replies small.
  const auto shortened = [](std::string text, std::size_t limit) {
    return text.size() > limit ? text.substr(0, limit) + "..." : text;
  };
  json e = {{"code", static_cast<int>(error.code())}, {"message", shortened(error.what(), 1000)}};
  if (!error.field().empty()) e["data"] = {{"field", shortened(error.field(), 200)}};
  return {{"jsonrpc", "2.0"}, {"id", id}, {"error", std::move(e)}};
}

std::string serialize(const json& response) {
  return response.dump(-1, ' ', false, json::error_handler_t::replace) + "\n";
}

}  // namespace hfts::service
