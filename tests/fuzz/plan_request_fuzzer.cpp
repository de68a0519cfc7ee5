// The params of a `plan` call (JSON text) through planRequestFromJson,
// inline scenes included, against a real catalog; nothing is planned. Its
// contract: RpcError(kInvalidParams) for every bad request, nothing else.

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_catalog.h"
#include "service/json_nesting.h"
#include "service/plan_request_json.h"
#include "service/rpc_error.h"

// The catalog is built before the first input, outside its time limit.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hfts::fuzz::catalog();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hfts;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  // The server rejects deeper texts before parsing them (json_rpc.h).
  service::JsonNesting nesting;
  for (const char c : text)
    if (nesting.consume(c) > 64) return -1;
  const nlohmann::json params = nlohmann::json::parse(text, nullptr, false);
  if (params.is_discarded()) return -1;
  try {
    service::planRequestFromJson(params, *fuzz::catalog(), service::PlanLimits{10.0, 2});
  } catch (const service::RpcError& e) {
    if (e.code() != service::ErrorCode::kInvalidParams) fuzz::contractViolated(e.what());
  }
  return 0;
}
