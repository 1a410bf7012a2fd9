#include "tests/raw_connection.h"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <arpa/inet.h>
#include <netinet/in.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace bumprad::test {

RawConnection::RawConnection(unsigned short port) {
  fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (fd_ < 0 || ::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0)
    throw std::runtime_error("cannot connect to port " + std::to_string(port));
}

RawConnection::~RawConnection() {
  if (fd_ >= 0) ::close(fd_);
}

void RawConnection::send(std::string_view bytes) {
  while (!bytes.empty()) {
    ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (n <= 0) throw std::runtime_error("the connection broke while sending");
    bytes.remove_prefix(std::size_t(n));
  }
}

void RawConnection::finish_sending() {
  ::shutdown(fd_, SHUT_WR);
}

std::string RawConnection::read_all(double seconds, std::string_view until) {
  std::string out;
  auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  for (;;) {
    if (!until.empty() && out.ends_with(until)) return out;
    auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return out;
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, int(left.count())) <= 0) return out;
    char buf[65536];
    ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
    if (n <= 0) return out;
    out.append(buf, std::size_t(n));
  }
}

std::vector<RawResponse> split_responses(std::string_view bytes,
                                         const std::vector<bool>& head_only) {
  std::vector<RawResponse> out;
  while (bytes.starts_with("HTTP/1.")) {
    RawResponse r;
    std::size_t end = bytes.find("\r\n\r\n");
    if (end == std::string_view::npos) break;
    r.head = std::string(bytes.substr(0, end + 4));
    r.status = std::stoi(r.head.substr(9, 3));
    bytes.remove_prefix(end + 4);
    std::size_t length = bytes.size();
    if (auto at = r.head.find("Content-Length: "); at != std::string::npos)
      length = std::stoul(r.head.substr(at + 16));
    if (out.size() < head_only.size() && head_only[out.size()]) length = 0;
    r.body = std::string(bytes.substr(0, length));
    bytes.remove_prefix(std::min(length, bytes.size()));
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace bumprad::test
