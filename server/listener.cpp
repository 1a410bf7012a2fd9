#include "server/listener.h"

#include <cstdio>

#include <boost/asio/strand.hpp>

namespace bumprad {

Listener::Listener(net::io_context& ioc, const net::ip::tcp::endpoint& endpoint,
                   SessionContext& context)
    : ioc_(ioc), acceptor_(net::make_strand(ioc)), context_(context) {
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(net::socket_base::reuse_address(true));
  acceptor_.bind(endpoint);
  acceptor_.listen(net::socket_base::max_listen_connections);
}

void Listener::stop() {
  net::post(acceptor_.get_executor(), [self = shared_from_this()] {
    beast::error_code ignored;
    self->acceptor_.close(ignored);
  });
}

void Listener::accept() {
  acceptor_.async_accept(
      net::make_strand(ioc_),
      [self = shared_from_this()](beast::error_code ec, net::ip::tcp::socket socket) {
        if (ec == net::error::operation_aborted) return;  // stopped
        if (!ec)
          std::make_shared<HttpSession>(std::move(socket), self->context_)->run();
        else
          std::fprintf(stderr, "accept: %s\n", ec.message().c_str());
        self->accept();
      });
}

}  // namespace bumprad
