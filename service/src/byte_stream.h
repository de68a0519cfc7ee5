#pragma once
// A connection's bytes: plain TCP, or TLS over it (hfts-server --tls-cert,
// docs/security.md). Used only on the server's I/O thread.

#include <asio/ip/tcp.hpp>
#include <asio/ssl/context.hpp>
#include <asio/ssl/stream.hpp>

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace hfts::service {

/// The server's TLS context from a PEM certificate chain and private key.
/// Throws std::runtime_error naming the file OpenSSL could not use.
asio::ssl::context serverTlsContext(const std::string& certificateFile, const std::string& keyFile);

class ByteStream {
 public:
  using Handler = std::function<void(const asio::error_code&, std::size_t)>;

  /// `tls` null: plain TCP. The context must outlive the stream.
  ByteStream(asio::ip::tcp::socket socket, asio::ssl::context* tls);

  asio::ip::tcp::socket& socket() { return tls_ ? tls_->next_layer() : plain_; }
  bool tls() const { return tls_.has_value(); }

  /// The TLS handshake (at once for plain TCP); `done` gets its error.
  void handshake(std::function<void(const asio::error_code&)> done);
  void readSome(asio::mutable_buffer buffer, Handler done);
  void write(const std::vector<asio::const_buffer>& buffers, Handler done);
  /// No more bytes to the peer (TCP half-close; with TLS without a
  /// close_notify, which the clients take as the end of the stream).
  void shutdownSend();
  void close();

 private:
  asio::ip::tcp::socket plain_;
  std::optional<asio::ssl::stream<asio::ip::tcp::socket>> tls_;
};

}  // namespace hfts::service
