// A small blocking HTTP/1.1 client over Boost.Beast for bumprad's API: one request per
// connection, whole answers or streamed ones. bumprad-client and the server tests use it.
#pragma once

#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>

namespace bumprad {

// The server could not be reached, or the connection broke.
class ConnectionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct HttpResponse {
  int status = 0;
  std::map<std::string, std::string> headers;  // names in lower case
  std::string body;

  std::string header(const std::string& lower_case_name) const;
  // For problem+json answers: "TITLE: DETAIL", else the status and body.
  std::string problem() const;
};

class HttpClient {
 public:
  HttpClient(std::string host, unsigned short port, double timeout_s = 60);

  HttpResponse request(std::string_view method, std::string_view target, std::string body = {},
                       std::string_view content_type = "application/json") const;
  HttpResponse get(std::string_view target) const { return request("GET", target); }

  // GETs a response that goes on (events, image streams) and hands each piece of its body
  // to `on_bytes` as it arrives, until the server ends it or `on_bytes` returns false.
  // Returns the status and headers.
  HttpResponse stream(std::string_view target,
                      const std::function<bool(std::string_view)>& on_bytes) const;

  std::string base_url() const;

 private:
  std::string host_;
  unsigned short port_;
  double timeout_s_;
};

// Splits "http://host:port" (or "host:port") into its parts; throws std::invalid_argument.
std::pair<std::string, unsigned short> parse_server_url(std::string_view url);

}  // namespace bumprad
