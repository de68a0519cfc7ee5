// What a client's bytes go through in hfts-server: the message framer (fed
// in pieces), the JSON-RPC envelope and the method dispatcher with a real
// catalog. `plan` calls are validated (planRequestFromJson) but not
// planned, `grasp.quality` is computed inline (the server uses a worker
// thread), and `reload` (which re-reads files) is not dispatched. A crash,
// an escaping exception or an internal-error reply is a finding: every bad
// input must get a clear JSON-RPC error.

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

service::MethodDispatcher& dispatcher() {
  static service::MethodDispatcher instance = [] {
    service::ServerOptions options;
    options.workers = 1;
    options.queue_capacity = 1;
    return service::MethodDispatcher(
        options, catalog(), [](std::function<void()> task) { task(); }, [] {});
  }();
  return instance;
}

void checkResponse(const json& response) {
  if (response.is_null()) return;  // a notification
  const auto error = response.find("error");
  if (error != response.end() && error->at("code") == static_cast<int>(ErrorCode::kInternalError))
    contractViolated("internal error reply: " + response.dump());
  service::serialize(response);
}

void run(const service::Call& call, const service::Caller& caller) {
  if (call.method == "reload") return;
  if (call.method != "plan" && call.method != "grasp.quality") {
    dispatcher().dispatch(call, caller, checkResponse);
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

void handle(std::string_view text, const service::Caller& caller) {
  const service::Message message = service::parseMessage(text);
  for (const service::MessageItem& item : message.items) {
    if (item.call) {
      run(*item.call, caller);
    } else {
      dispatcher().logRejected(caller, item.error);
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
  const service::Caller caller{"fuzz:1", true, std::make_shared<service::CancelRegistry>()};
  service::MessageFramer framer(fuzz::kMaxMessageBytes);
  std::vector<std::string> messages;
  // Pieces of a length that varies with the input, as reads from a socket.
  const std::size_t piece = 1 + size % 61;
  for (std::size_t at = 0; at < size; at += piece)
    if (!framer.feed(bytes.substr(at, piece), messages)) break;
  for (const std::string& message : messages) fuzz::handle(message, caller);
  if (!framer.inUnclosedText()) {
    const std::string rest = framer.takeRemainder();
    if (!rest.empty()) fuzz::handle(rest, caller);
  }
  return 0;
}
