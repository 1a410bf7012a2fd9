// Accepts connections on the bound address and hands each to its own HttpSession. When
// accepting fails for want of resources (no file descriptors left), it waits before trying
// again, longer each time up to a second, and logs the failures at most every 10 seconds.
#pragma once

#include <chrono>
#include <memory>

#include <boost/asio/ip/tcp.hpp>

#include "server/http_session.h"

namespace bumprad {

class Listener : public std::enable_shared_from_this<Listener> {
 public:
  // Throws boost::system::system_error if the address cannot be bound.
  Listener(net::io_context& ioc, const net::ip::tcp::endpoint& endpoint, SessionContext& context);
  void run() { accept(); }
  void stop();
  unsigned short port() const { return acceptor_.local_endpoint().port(); }

 private:
  void accept();
  void on_error(beast::error_code ec);
  net::io_context& ioc_;
  net::ip::tcp::acceptor acceptor_;
  SessionContext& context_;
  net::steady_timer backoff_;
  std::chrono::milliseconds delay_{0};
  std::chrono::steady_clock::time_point last_log_;
  int unlogged_ = 0;
};

}  // namespace bumprad
