#include "service/rpc_error.h"

#include <gtest/gtest.h>

namespace hfts::service {
namespace {

TEST(RpcError, InvalidParamsNameTheirField) {
  try {
    throwInvalidParam("object_pose.orientation", "is a quaternion of zero norm");
    FAIL();
  } catch (const RpcError& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidParams);
    EXPECT_EQ(e.field(), "object_pose.orientation");
    EXPECT_STREQ(e.what(), "object_pose.orientation: is a quaternion of zero norm");
  }
}

TEST(RpcError, ThePlannersMessagesTakeTheServicesForm) {
  const RpcError quoted = invalidParamFromPlanner("'contacts[0].normal' must be a unit vector");
  EXPECT_EQ(quoted.field(), "contacts[0].normal");
  EXPECT_STREQ(quoted.what(), "contacts[0].normal: must be a unit vector");
  const RpcError parameter =
      invalidParamFromPlanner("parameters: '5' is not a valid value for 'p_max' (range 0.:.05:1.)");
  EXPECT_EQ(parameter.field(), "parameters.p_max");
  EXPECT_STREQ(parameter.what(),
               "parameters.p_max: '5' is not a valid value for 'p_max' (range 0.:.05:1.)");
  const RpcError prefixed = invalidParamFromPlanner("start: values must be finite");
  EXPECT_EQ(prefixed.field(), "start");
  EXPECT_STREQ(prefixed.what(), "start: values must be finite");
  const RpcError plain = invalidParamFromPlanner("the request must be a JSON object");
  EXPECT_EQ(plain.field(), "");
  EXPECT_EQ(plain.code(), ErrorCode::kInvalidParams);
}

TEST(RpcError, CodesFollowJsonRpcAndTheProtocol) {
  EXPECT_EQ(static_cast<int>(ErrorCode::kParseError), -32700);
  EXPECT_EQ(static_cast<int>(ErrorCode::kInvalidRequest), -32600);
  EXPECT_EQ(static_cast<int>(ErrorCode::kMethodNotFound), -32601);
  EXPECT_EQ(static_cast<int>(ErrorCode::kInvalidParams), -32602);
  EXPECT_EQ(static_cast<int>(ErrorCode::kBusy), -32001);
  EXPECT_STREQ(toString(ErrorCode::kMessageTooLarge), "message_too_large");
}

}  // namespace
}  // namespace hfts::service
