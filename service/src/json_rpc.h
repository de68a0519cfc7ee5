#pragma once
// The JSON-RPC 2.0 envelope: a message's text -> calls, and the response
// objects (https://www.jsonrpc.org/specification).

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "service/rpc_error.h"

namespace hfts::service {

/// One call: a request, or a notification (no "id": no response).
struct Call {
  nlohmann::json id;  ///< null for notifications
  bool notification = false;
  std::string method;
  nlohmann::json params = nlohmann::json::object();  ///< as sent; {} when absent
};

/// One element of a message: a call, or the error response to send for an
/// element that is not a valid request.
struct MessageItem {
  std::optional<Call> call;
  nlohmann::json error;
};

struct Message {
  bool batch = false;  ///< the response is an array (unless no element needs one)
  std::vector<MessageItem> items;
};

/// The most calls one batch may hold, and the deepest nesting a message
/// may have (deeper texts are rejected before they are parsed).
inline constexpr std::size_t kMaxBatchCalls = 1024;
inline constexpr int kMaxNestingDepth = 64;

/// Parses one framed message. Never throws: invalid JSON (also an empty
/// line) gives one item with a parse error, an empty or oversized batch
/// one with an invalid-request error.
Message parseMessage(std::string_view text);

nlohmann::json resultResponse(const nlohmann::json& id, nlohmann::json result);
nlohmann::json errorResponse(const nlohmann::json& id, const RpcError& error);

/// The response as one line: compact JSON (invalid UTF-8 replaced) + "\n".
std::string serialize(const nlohmann::json& response);

}  // namespace hfts::service
