#include "client/rpc_client.h"

#include <asio/connect.hpp>
#include <asio/ip/tcp.hpp>
#include <asio/read_until.hpp>
#include <asio/streambuf.hpp>
#include <asio/write.hpp>
#include <nlohmann/json.hpp>

#include <istream>

namespace hfts::client {

using asio::ip::tcp;
using nlohmann::json;

class RpcClient::Impl {
 public:
  Impl(const std::string& host, std::uint16_t port) : socket_(io_) {
    const std::string where = host + ":" + std::to_string(port);
    asio::error_code ec;
    tcp::resolver resolver(io_);
    const auto endpoints = resolver.resolve(host, std::to_string(port), ec);
    if (!ec) asio::connect(socket_, endpoints, ec);
    if (ec) throw ConnectionError("cannot connect to " + where + ": " + ec.message());
    socket_.set_option(tcp::no_delay(true), ec);
  }

  json call(const std::string& method, const json& params) {
    const std::uint64_t id = ++last_id_;
    const std::string line =
        json{{"jsonrpc", "2.0"}, {"id", id}, {"method", method}, {"params", params}}.dump() + "\n";
    asio::error_code ec;
    asio::write(socket_, asio::buffer(line), ec);
    if (ec) throw ConnectionError("cannot send the request: " + ec.message());
    for (;;) {
      const json response = readResponse();
      const auto responseId = response.find("id");
      // An error with a null id answers a message the server could not read: this one.
      if (responseId != response.end() && (*responseId == id || responseId->is_null()))
        return resultOf(response);
    }
  }

 private:
  json readResponse() {
    asio::error_code ec;
    asio::read_until(socket_, buffer_, '\n', ec);
    if (ec)
      throw ConnectionError(ec == asio::error::eof ? "the server closed the connection"
                                                   : "cannot read the response: " + ec.message());
    std::istream in(&buffer_);
    std::string text;
    std::getline(in, text);
    try {
      json response = json::parse(text);
      if (response.is_object()) return response;
    } catch (const json::exception&) {
    }
    throw ConnectionError("the server sent something that is not a JSON-RPC response");
  }

  static json resultOf(const json& response) {
    if (response.contains("result")) return response["result"];
    const auto error = response.find("error");
    if (error == response.end() || !error->is_object())
      throw ConnectionError("the server sent a response without result or error");
    const auto text = [](const json& object, const char* key) {
      const auto it = object.find(key);
      return it != object.end() && it->is_string() ? it->get<std::string>() : std::string();
    };
    const auto code = error->find("code");
    const auto data = error->find("data");
    throw RpcCallError(code != error->end() && code->is_number_integer() ? code->get<int>() : 0,
                       text(*error, "message"),
                       data != error->end() && data->is_object() ? text(*data, "field") : "");
  }

  asio::io_context io_;
  tcp::socket socket_;
  asio::streambuf buffer_;
  std::uint64_t last_id_ = 0;
};

RpcClient::RpcClient(const std::string& host, std::uint16_t port)
    : impl_(std::make_unique<Impl>(host, port)) {}
RpcClient::~RpcClient() = default;

json RpcClient::call(const std::string& method, const json& params) {
  return impl_->call(method, params);
}

}  // namespace hfts::client
