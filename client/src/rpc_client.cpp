#include "client/rpc_client.h"

#include <asio/connect.hpp>
#include <asio/ip/tcp.hpp>
#include <asio/read_until.hpp>
#include <asio/ssl/context.hpp>
#include <asio/ssl/host_name_verification.hpp>
#include <asio/ssl/stream.hpp>
#include <asio/streambuf.hpp>
#include <asio/write.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <istream>
#include <memory>
#include <optional>
#include <thread>

namespace hfts::client {

using asio::ip::tcp;
using nlohmann::json;

namespace {

/// The transport failed: worth connecting again (unlike a reply that is
/// not JSON-RPC, which another attempt would not mend).
class LostConnection : public ConnectionError {
 public:
  using ConnectionError::ConnectionError;
};

bool repeatable(const std::string& method) {
  return method != "cancel" && method != "shutdown";
}

}  // namespace

std::string tokenFrom(const std::string& tokenFile) {
  const auto trimmed = [](std::string text) {
    const auto space = [](unsigned char c) { return std::isspace(c) != 0; };
    text.erase(text.begin(), std::find_if_not(text.begin(), text.end(), space));
    text.erase(std::find_if_not(text.rbegin(), text.rend(), space).base(), text.end());
    return text;
  };
  if (tokenFile.empty()) {
    const char* fromEnvironment = std::getenv("HFTS_TOKEN");
    return fromEnvironment != nullptr ? trimmed(fromEnvironment) : std::string();
  }
  std::ifstream in(tokenFile);
  std::string line;
  if (!in || !std::getline(in, line))
    throw std::runtime_error("cannot read a token from '" + tokenFile + "'");
  std::string token = trimmed(line);
  if (token.empty())
    throw std::runtime_error("'" + tokenFile + "' holds no token on its first line");
  return token;
}

class RpcClient::Impl {
 public:
  Impl(std::string host, std::uint16_t port, RetryPolicy retry, Access access)
      : host_(std::move(host)),
        port_(port),
        retry_(std::move(retry)),
        access_(std::move(access)),
        socket_(io_) {
    if (access_.tls) tls_context_.emplace(clientTlsContext(access_.ca_file));
    if (retry_.retries < 0) throw std::invalid_argument("retries must be >= 0");
    if (!(retry_.backoff >= 0.0)) throw std::invalid_argument("backoff must be >= 0 s");
    withRetries(true, [this] { connect(); });
  }

  json call(const std::string& method, const json& params) {
    json result;
    withRetries(repeatable(method), [&] {
      if (!socket_.is_open()) connect();
      result = send(method, params);
    });
    return result;
  }

  int reconnections = 0;

 private:
  /// Runs `attempt` until it does not lose the connection, at most
  /// 1 + retries times, waiting the policy's backoff in between.
  template <typename Attempt>
  void withRetries(bool allowed, Attempt attempt) {
    const int attempts = allowed ? 1 + retry_.retries : 1;
    double wait = retry_.backoff;
    for (int n = 1;; ++n) {
      try {
        attempt();
        return;
      } catch (const LostConnection& e) {
        asio::error_code ignored;
        tls_.reset();
        socket_.close(ignored);
        buffer_.consume(buffer_.size());
        if (n >= attempts) throw;
        if (retry_.on_retry) retry_.on_retry(e.what(), n + 1);
        std::this_thread::sleep_for(std::chrono::duration<double>(wait));
        wait = std::min(2 * wait, 2.0);
        ++reconnections;
      }
    }
  }

  void connect() {
    const std::string where = host_ + ":" + std::to_string(port_);
    asio::error_code ec;
    tcp::resolver resolver(io_);
    const auto endpoints = resolver.resolve(host_, std::to_string(port_), ec);
    if (!ec) asio::connect(socket_, endpoints, ec);
    if (ec) throw LostConnection("cannot connect to " + where + ": " + ec.message());
    socket_.set_option(tcp::no_delay(true), ec);
    if (tls_context_) {
      tls_ = std::make_unique<asio::ssl::stream<tcp::socket&>>(socket_, *tls_context_);
      tls_->set_verify_mode(asio::ssl::verify_peer);
      tls_->set_verify_callback(asio::ssl::host_name_verification(host_));
      // The server name for servers that hold several certificates (SNI;
      // never an address). SSL_set_tlsext_host_name's macro, without its cast.
      asio::error_code notAnAddress;
      asio::ip::make_address(host_, notAnAddress);
      if (notAnAddress)
        SSL_ctrl(tls_->native_handle(), SSL_CTRL_SET_TLSEXT_HOSTNAME, TLSEXT_NAMETYPE_host_name,
                 static_cast<void*>(const_cast<char*>(host_.c_str())));
      tls_->handshake(asio::ssl::stream_base::client, ec);
      if (ec) {
        // A certificate that does not verify will not verify on a retry.
        const bool certificate = ec.category() == asio::error::get_ssl_category();
        const std::string why = "TLS handshake with " + where + " failed: " + ec.message() +
                                (certificate ? " (is --ca-file the server's CA?)" : "");
        if (certificate) {
          tls_.reset();
          socket_.close(ec);
          throw ConnectionError(why);
        }
        throw LostConnection(why);
      }
    }
    if (!access_.token.empty()) send("auth", {{"token", access_.token}});
  }

  static asio::ssl::context clientTlsContext(const std::string& caFile) {
    asio::ssl::context context(asio::ssl::context::tls_client);
    context.set_options(asio::ssl::context::default_workarounds | asio::ssl::context::no_sslv2 |
                        asio::ssl::context::no_sslv3 | asio::ssl::context::no_tlsv1 |
                        asio::ssl::context::no_tlsv1_1);
    asio::error_code ec;
    if (caFile.empty())
      context.set_default_verify_paths(ec);
    else
      context.load_verify_file(caFile, ec);
    if (ec)
      throw ConnectionError("cannot load the CA certificates" +
                            (caFile.empty() ? std::string() : " of '" + caFile + "'") + ": " +
                            ec.message());
    return context;
  }

  json send(const std::string& method, const json& params) {
    const std::uint64_t id = ++last_id_;
    const std::string line =
        json{{"jsonrpc", "2.0"}, {"id", id}, {"method", method}, {"params", params}}.dump() + "\n";
    asio::error_code ec;
    if (tls_)
      asio::write(*tls_, asio::buffer(line), ec);
    else
      asio::write(socket_, asio::buffer(line), ec);
    if (ec) throw LostConnection("cannot send the request: " + ec.message());
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
    if (tls_)
      asio::read_until(*tls_, buffer_, '\n', ec);
    else
      asio::read_until(socket_, buffer_, '\n', ec);
    // The server ends a TLS connection without close_notify (a TCP
    // half-close): the end of the stream, as for plain TCP.
    if (ec == asio::error::eof || ec == asio::ssl::error::stream_truncated)
      throw LostConnection("the server closed the connection");
    if (ec) throw LostConnection("cannot read the response: " + ec.message());
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

  std::string host_;
  std::uint16_t port_;
  RetryPolicy retry_;
  Access access_;
  asio::io_context io_;
  std::optional<asio::ssl::context> tls_context_;
  tcp::socket socket_;
  std::unique_ptr<asio::ssl::stream<tcp::socket&>> tls_;  // over socket_, when TLS
  asio::streambuf buffer_;
  std::uint64_t last_id_ = 0;
};

RpcClient::RpcClient(const std::string& host, std::uint16_t port, RetryPolicy retry, Access access)
    : impl_(std::make_unique<Impl>(host, port, std::move(retry), std::move(access))) {}
RpcClient::~RpcClient() = default;

json RpcClient::call(const std::string& method, const json& params) {
  return impl_->call(method, params);
}

int RpcClient::reconnections() const {
  return impl_->reconnections;
}

}  // namespace hfts::client
