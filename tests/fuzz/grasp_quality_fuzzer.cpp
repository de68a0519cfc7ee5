// A `grasp.quality` request: as params of the service (graspQualityJson,
// with the catalog's objects) and as the raw text hfts-quality reads
// (graspQualityRequestFromJson). Both parse and compute epsilon; the
// parser caps contacts at 64 and cone edges at 64, which keeps one input
// fast. Bad requests must throw RpcError(kInvalidParams), respectively
// std::invalid_argument.

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "fuzz_catalog.h"
#include "grasp/grasp_quality_json.h"
#include "service/catalog_json.h"
#include "service/json_nesting.h"
#include "service/rpc_error.h"

namespace {

void asServiceParams(const std::string& text) {
  using namespace hfts;
  service::JsonNesting nesting;  // the server's limit (json_rpc.h)
  for (const char c : text)
    if (nesting.consume(c) > 64) return;
  const nlohmann::json params = nlohmann::json::parse(text, nullptr, false);
  if (params.is_discarded()) return;
  try {
    service::graspQualityJson(params, *fuzz::catalog());
  } catch (const service::RpcError& e) {
    if (e.code() != service::ErrorCode::kInvalidParams) fuzz::contractViolated(e.what());
  }
}

void asQualityFile(const std::string& text) {
  using namespace hfts;
  try {
    grasp::graspQualityResultToJson(grasp::graspQuality(grasp::graspQualityRequestFromJson(text)));
  } catch (const std::invalid_argument&) {
  }
}

}  // namespace

// The catalog is built before the first input, outside its time limit.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hfts::fuzz::catalog();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  asServiceParams(text);
  asQualityFile(text);
  return 0;
}
