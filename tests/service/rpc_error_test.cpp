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

TEST(RpcError, ALibrarysInvalidArgumentKeepsItsFieldAndForm) {
  const RpcError plain =
      invalidParam(InvalidArgument("contacts[0].normal", "must be a unit vector"));
  EXPECT_EQ(plain.code(), ErrorCode::kInvalidParams);
  EXPECT_EQ(plain.field(), "contacts[0].normal");
  EXPECT_STREQ(plain.what(), "contacts[0].normal: must be a unit vector");
  const RpcError nested =
      invalidParam(InvalidArgument("obstacles[2].size", "must be > 0"), "scene.");
  EXPECT_EQ(nested.field(), "scene.obstacles[2].size");
  EXPECT_STREQ(nested.what(), "scene.obstacles[2].size: must be > 0");
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
