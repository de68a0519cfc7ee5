#include "json_rpc.h"

#include <gtest/gtest.h>

namespace hfts::service {
namespace {

using nlohmann::json;

int errorCode(const MessageItem& item) {
  EXPECT_FALSE(item.call.has_value());
  return item.error.at("error").at("code").get<int>();
}

TEST(JsonRpc, ParsesARequest) {
  const Message m = parseMessage(
      R"({"jsonrpc": "2.0", "id": "x", "method": "plan", "params": {"scene": "table"}})");
  ASSERT_FALSE(m.batch);
  ASSERT_EQ(m.items.size(), 1u);
  const Call& call = *m.items[0].call;
  EXPECT_EQ(call.id, "x");
  EXPECT_FALSE(call.notification);
  EXPECT_EQ(call.method, "plan");
  EXPECT_EQ(call.params, json({{"scene", "table"}}));
}

TEST(JsonRpc, ANotificationHasNoIdAndParamsDefaultToAnObject) {
  const Message m = parseMessage(R"({"jsonrpc": "2.0", "method": "server.info"})");
  EXPECT_TRUE(m.items[0].call->notification);
  EXPECT_EQ(m.items[0].call->params, json::object());
  EXPECT_FALSE(
      parseMessage(R"({"jsonrpc":"2.0","id":null,"method":"a"})").items[0].call->notification);
}

TEST(JsonRpc, ParseErrorsAndEmptyLinesAreParseErrors) {
  for (const char* text : {"", "  \r", "{", "nope", "NaN", "[1e400]", "{\"a\":1}}"})
    EXPECT_EQ(errorCode(parseMessage(text).items.at(0)), -32700) << text;
  EXPECT_EQ(parseMessage("").items[0].error.at("error").at("message"), "parse error: empty line");
}

TEST(JsonRpc, InvalidRequestsKeepTheirIdWhenItIsValid) {
  const Message m = parseMessage(R"({"jsonrpc": "2.0", "id": 4, "method": 1})");
  EXPECT_EQ(errorCode(m.items[0]), -32600);
  EXPECT_EQ(m.items[0].error.at("id"), 4);
  EXPECT_EQ(parseMessage(R"({"jsonrpc": "2.0", "id": [4], "method": "a"})").items[0].error.at("id"),
            nullptr);
  for (const char* text : {R"({"id": 1, "method": "a"})", R"({"jsonrpc": 2.0, "method": "a"})",
                           R"({"jsonrpc": "2.0", "method": "a", "params": "x"})",
                           R"({"jsonrpc": "2.0", "method": "a", "other": 1})", "5", "[]"})
    EXPECT_EQ(errorCode(parseMessage(text).items.at(0)), -32600) << text;
}

TEST(JsonRpc, RejectsDeepNestingBeforeParsing) {
  const std::string deep = std::string(65, '[') + std::string(65, ']');
  EXPECT_EQ(errorCode(parseMessage(deep).items[0]), -32600);
  const std::string ok = R"({"jsonrpc":"2.0","method":"a","params":{"x":)" + std::string(60, '[') +
                         std::string(60, ']') + "}}";
  EXPECT_TRUE(parseMessage(ok).items[0].call.has_value());
  EXPECT_TRUE(
      parseMessage(
          R"({"jsonrpc":"2.0","method":"[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[["})")
          .items[0]
          .call.has_value())
      << "brackets in strings do not count";
}

TEST(JsonRpc, ABatchHasOneItemPerElement) {
  const Message m = parseMessage(R"([{"jsonrpc":"2.0","id":1,"method":"a"}, 7,
                                     {"jsonrpc":"2.0","method":"b"}])");
  EXPECT_TRUE(m.batch);
  ASSERT_EQ(m.items.size(), 3u);
  EXPECT_EQ(m.items[0].call->method, "a");
  EXPECT_EQ(errorCode(m.items[1]), -32600);
  EXPECT_TRUE(m.items[2].call->notification);
}

TEST(JsonRpc, ABatchHoldsAtMostTheLimit) {
  json batch = json::array();
  for (std::size_t i = 0; i <= kMaxBatchCalls; ++i)
    batch.push_back({{"jsonrpc", "2.0"}, {"method", "a"}});
  EXPECT_EQ(errorCode(parseMessage(batch.dump()).items[0]), -32600);
  batch.erase(batch.begin());
  EXPECT_EQ(parseMessage(batch.dump()).items.size(), kMaxBatchCalls);
}

TEST(JsonRpc, ResponsesFollowTheSpecification) {
  EXPECT_EQ(resultResponse(3, {{"a", 1}}),
            json::parse(R"({"jsonrpc":"2.0","id":3,"result":{"a":1}})"));
  const json e =
      errorResponse("q", RpcError(ErrorCode::kInvalidParams, "seed: must be >= 0", "seed"));
  EXPECT_EQ(e, json::parse(R"({"jsonrpc":"2.0","id":"q","error":{"code":-32602,
                               "message":"seed: must be >= 0","data":{"field":"seed"}}})"));
  EXPECT_FALSE(
      errorResponse(nullptr, RpcError(ErrorCode::kBusy, "busy")).at("error").contains("data"));
}

TEST(JsonRpc, ErrorMessagesAreShortenedAndSerialisedAsValidUtf8) {
  const json e =
      errorResponse(1, RpcError(ErrorCode::kMethodNotFound, std::string(5000, 'x') + "\xff"));
  EXPECT_LT(e.at("error").at("message").get<std::string>().size(), 1010u);
  const std::string line =
      serialize(errorResponse(1, RpcError(ErrorCode::kParseError, "bad \xff byte")));
  EXPECT_EQ(line.back(), '\n');
  EXPECT_EQ(line.find('\n'), line.size() - 1);
  EXPECT_TRUE(json::accept(line));
}

}  // namespace
}  // namespace hfts::service
