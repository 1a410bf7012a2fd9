#include "server/listener.h"

#include <algorithm>
#include <cstdio>

#include <boost/asio/strand.hpp>

namespace bumprad {

Listener::Listener(net::io_context& ioc, const net::ip::tcp::endpoint& endpoint,
                   SessionContext& context)
    : ioc_(ioc),
      acceptor_(net::make_strand(ioc)),
      context_(context),
      backoff_(acceptor_.get_executor()) {
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(net::socket_base::reuse_address(true));
  acceptor_.bind(endpoint);
  acceptor_.listen(net::socket_base::max_listen_connections);
}

void Listener::stop() {
  net::post(acceptor_.get_executor(), [self = shared_from_this()] {
    beast::error_code ignored;
    self->acceptor_.close(ignored);
    self->backoff_.cancel();
  });
}

void Listener::accept() {
  acceptor_.async_accept(
      net::make_strand(ioc_),
      [self = shared_from_this()](beast::error_code ec, net::ip::tcp::socket socket) {
        if (ec == net::error::operation_aborted) return;  // stopped
        if (ec) return self->on_error(ec);
        self->delay_ = std::chrono::milliseconds(0);
        std::make_shared<HttpSession>(std::move(socket), self->context_)->run();
        self->accept();
      });
}

void Listener::on_error(beast::error_code ec) {
  // Out of descriptors or memory, accepting again at once fails again at once: a busy loop.
  using namespace std::chrono_literals;
  delay_ = std::clamp(delay_ * 2, 10ms, std::chrono::milliseconds(1000));
  auto now = std::chrono::steady_clock::now();
  if (now - last_log_ >= 10s) {
    std::fprintf(stderr, "accept: %s (%d more since the last report); retrying in %lld ms\n",
                 ec.message().c_str(), unlogged_, static_cast<long long>(delay_.count()));
    last_log_ = now;
    unlogged_ = 0;
  } else {
    ++unlogged_;
  }
  backoff_.expires_after(delay_);
  backoff_.async_wait([self = shared_from_this()](beast::error_code wait) {
    if (!wait && self->acceptor_.is_open()) self->accept();
  });
}

}  // namespace bumprad
