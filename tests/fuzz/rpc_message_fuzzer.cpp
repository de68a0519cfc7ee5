// What a client's bytes go through in hfts-server: the message framer (fed
// in pieces), the JSON-RPC envelope and the method dispatcher with a real
// catalog. `plan` calls are validated (planRequestFromJson) but not
// planned, `grasp.quality` is computed inline (the server uses a worker
// thread), and `reload` (which re-reads files) is not dispatched. Every
// input goes to two dispatchers: one without tokens, and one with a plan
// and an admin token (tokens below), where calls before a good `auth` are
// refused. A crash, an escaping exception or an internal-error reply is a
// finding: every bad input must get a clear JSON-RPC error.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_catalog.h"
#include "json_rpc.h"
#include "method_dispatcher.h"
#include "service/catalog_json.h"
#include "service/message_framer.h"
#include "service/plan_request_json.h"

namespace hfts::fuzz {
namespace {

using nlohmann::json;
using service::ErrorCode;

constexpr std::size_t kMaxMessageBytes = 1u << 16;

/// The tokens of the dispatcher that authenticates (seed auth_plan.jsonl
/// and auth_admin.jsonl use them).
constexpr const char* kTokens =
    "plan fuzz-plan-token-0123456789 planner\n"
    "admin fuzz-admin-token-0123456789 operator\n";

service::MethodDispatcher makeDispatcher(bool withTokens) {
  service::ServerOptions options;
  options.workers = 1;
  options.queue_capacity = 1;
  return service::MethodDispatcher(
      options, catalog(),
      withTokens ? std::make_shared<const service::TokenTable>(
                       service::TokenTable::parse(kTokens, "fuzz tokens"))
                 : nullptr,
      [](std::function<void()> task) { task(); },
      [](std::chrono::milliseconds, std::function<void()> task) { task(); }, [] {});
}

service::MethodDispatcher& dispatcher(bool withTokens) {
  static service::MethodDispatcher open = makeDispatcher(false);
  static service::MethodDispatcher guarded = makeDispatcher(true);
  return withTokens ? guarded : open;
}

void checkResponse(const json& response) {
  if (response.is_null()) return;  // a notification
  const auto error = response.find("error");
  if (error != response.end() && error->at("code") == static_cast<int>(ErrorCode::kInternalError))
    contractViolated("internal error reply: " + response.dump());
  service::serialize(response);
}

void run(const service::Call& call, const service::Caller& caller, bool withTokens) {
  if (call.method == "reload") return;
  if (call.method != "plan" && call.method != "grasp.quality") {
    dispatcher(withTokens).dispatch(call, caller, checkResponse);
    return;
  }
  // The dispatcher runs these on worker threads; here they run inline.
  try {
    if (call.method == "plan")
      service::planRequestFromJson(call.params, *catalog(), service::PlanLimits{});
    else
      service::graspQualityJson(call.params, *catalog());
  } catch (const service::RpcError& e) {
    if (e.code() != ErrorCode::kInvalidParams) contractViolated(e.what());
  }
}

void handle(std::string_view text, const service::Caller& caller, bool withTokens) {
  const service::Message message = service::parseMessage(text);
  for (const service::MessageItem& item : message.items) {
    if (item.call) {
      run(*item.call, caller, withTokens);
    } else {
      dispatcher(withTokens).logRejected(caller, item.error);
      service::serialize(item.error);
    }
  }
}

}  // namespace
}  // namespace hfts::fuzz

// The catalog is built before the first input, outside its time limit.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hfts::fuzz::catalog();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hfts;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  for (const bool withTokens : {false, true}) {
    // A new connection for each dispatcher: its session starts unauthenticated.
    const service::Caller caller{"fuzz:1", "fuzz", std::make_shared<service::CancelRegistry>()};
    service::MessageFramer framer(fuzz::kMaxMessageBytes);
    std::vector<std::string> messages;
    // Pieces of a length that varies with the input, as reads from a socket.
    const std::size_t piece = 1 + size % 61;
    for (std::size_t at = 0; at < size; at += piece)
      if (!framer.feed(bytes.substr(at, piece), messages)) break;
    for (const std::string& message : messages) fuzz::handle(message, caller, withTokens);
    if (!framer.inUnclosedText()) {
      const std::string rest = framer.takeRemainder();
      if (!rest.empty()) fuzz::handle(rest, caller, withTokens);
    }
  }
  return 0;
}
