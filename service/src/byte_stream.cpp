#include "byte_stream.h"

#include <asio/post.hpp>
#include <asio/write.hpp>

#include <stdexcept>

namespace hfts::service {

using asio::ip::tcp;

asio::ssl::context serverTlsContext(const std::string& certificateFile,
                                    const std::string& keyFile) {
  asio::ssl::context context(asio::ssl::context::tls_server);
  // TLS 1.2 and 1.3 only.
  context.set_options(asio::ssl::context::default_workarounds | asio::ssl::context::no_sslv2 |
                      asio::ssl::context::no_sslv3 | asio::ssl::context::no_tlsv1 |
                      asio::ssl::context::no_tlsv1_1 | asio::ssl::context::single_dh_use);
  asio::error_code ec;
  context.use_certificate_chain_file(certificateFile, ec);
  if (ec)
    throw std::runtime_error("cannot use the TLS certificate '" + certificateFile +
                             "': " + ec.message());
  context.use_private_key_file(keyFile, asio::ssl::context::pem, ec);
  if (ec)
    throw std::runtime_error("cannot use the TLS private key '" + keyFile + "': " + ec.message());
  return context;
}

ByteStream::ByteStream(tcp::socket socket, asio::ssl::context* tls)
    : plain_(socket.get_executor()) {
  if (tls != nullptr)
    tls_.emplace(std::move(socket), *tls);
  else
    plain_ = std::move(socket);
}

void ByteStream::handshake(std::function<void(const asio::error_code&)> done) {
  if (!tls_) {
    asio::post(plain_.get_executor(), [done = std::move(done)] { done({}); });
    return;
  }
  tls_->async_handshake(asio::ssl::stream_base::server, std::move(done));
}

void ByteStream::readSome(asio::mutable_buffer buffer, Handler done) {
  if (tls_)
    tls_->async_read_some(buffer, std::move(done));
  else
    plain_.async_read_some(buffer, std::move(done));
}

void ByteStream::write(const std::vector<asio::const_buffer>& buffers, Handler done) {
  if (tls_)
    asio::async_write(*tls_, buffers, std::move(done));
  else
    asio::async_write(plain_, buffers, std::move(done));
}

void ByteStream::shutdownSend() {
  asio::error_code ignored;
  socket().shutdown(tcp::socket::shutdown_send, ignored);
}

void ByteStream::close() {
  asio::error_code ignored;
  socket().close(ignored);
}

}  // namespace hfts::service
