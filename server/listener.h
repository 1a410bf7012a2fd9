// Accepts connections on the bound address and hands each to its own HttpSession.
#pragma once

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
  net::io_context& ioc_;
  net::ip::tcp::acceptor acceptor_;
  SessionContext& context_;
};

}  // namespace bumprad
