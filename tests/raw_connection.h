// A plain TCP connection to a loopback port for the tests that speak HTTP badly on purpose:
// pipelined, truncated, slow or malformed bytes that no HTTP client library would send.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace bumprad::test {

class RawConnection {
 public:
  explicit RawConnection(unsigned short port);  // throws std::runtime_error
  ~RawConnection();
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;

  void send(std::string_view bytes);  // all of them; throws if the connection breaks
  void finish_sending();              // half-close: the server reads end of stream
  // Everything the server sends until it closes the connection, `seconds` pass, or (when
  // given) what it sent so far ends with `until`.
  std::string read_all(double seconds = 10, std::string_view until = {});

 private:
  int fd_ = -1;
};

// One HTTP response as it came over the wire.
struct RawResponse {
  int status = 0;
  std::string head;  // status line and headers
  std::string body;
};
// The responses in `bytes`, one after another, each as long as its Content-Length says (or
// to the end, without one). `head_only` lists which are answers to HEAD: they have no body.
std::vector<RawResponse> split_responses(std::string_view bytes,
                                         const std::vector<bool>& head_only = {});

}  // namespace bumprad::test
