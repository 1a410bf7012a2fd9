#include "clients/http_client.h"

#include <charconv>
#include <chrono>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <nlohmann/json.hpp>

namespace bumprad {

namespace beast = boost::beast;
namespace http = beast::http;
namespace net = boost::asio;

namespace {

// A connected stream with a deadline for everything done on it.
struct Connection {
  net::io_context ioc;
  beast::tcp_stream stream{ioc};

  Connection(const std::string& host, unsigned short port, double timeout_s) {
    stream.expires_after(std::chrono::milliseconds(long(timeout_s * 1000)));
    try {
      net::ip::tcp::resolver resolver(ioc);
      stream.connect(resolver.resolve(host, std::to_string(port)));
    } catch (const boost::system::system_error& e) {
      throw ConnectionError("cannot connect to http://" + host + ":" + std::to_string(port) + ": " +
                            e.code().message() + " (is `bumprad serve` running?)");
    }
  }

  void send(std::string_view method, std::string_view target, const std::string& host,
            std::string body, std::string_view content_type) {
    http::request<http::string_body> req{http::string_to_verb(method), target, 11};
    req.set(http::field::host, host);
    req.set(http::field::user_agent, "bumprad-client");
    if (!body.empty()) req.set(http::field::content_type, content_type);
    req.body() = std::move(body);
    req.prepare_payload();
    http::write(stream, req);
  }
};

void copy_headers(const http::fields& fields, HttpResponse& out) {
  for (const auto& f : fields) {
    std::string name(f.name_string());
    for (char& c : name) c = char(std::tolower(static_cast<unsigned char>(c)));
    out.headers[name] = std::string(f.value());
  }
}

}  // namespace

std::string HttpResponse::header(const std::string& name) const {
  auto it = headers.find(name);
  return it == headers.end() ? "" : it->second;
}

std::string HttpResponse::problem() const {
  if (header("content-type") == "application/problem+json") {
    auto p = nlohmann::json::parse(body, nullptr, false);
    if (p.is_object())
      return p.value("title", "error") + " (" + std::to_string(status) +
             "): " + p.value("detail", "");
  }
  return "HTTP " + std::to_string(status) + ": " + body.substr(0, 200);
}

HttpClient::HttpClient(std::string host, unsigned short port, double timeout_s)
    : host_(std::move(host)), port_(port), timeout_s_(timeout_s) {}

std::string HttpClient::base_url() const {
  return "http://" + host_ + ":" + std::to_string(port_);
}

HttpResponse HttpClient::request(std::string_view method, std::string_view target, std::string body,
                                 std::string_view content_type) const {
  Connection c(host_, port_, timeout_s_);
  try {
    c.send(method, target, host_, std::move(body), content_type);
    beast::flat_buffer buffer;
    http::response_parser<http::string_body> parser;
    parser.body_limit(std::uint64_t(1) << 31);
    http::read(c.stream, buffer, parser);
    HttpResponse out;
    out.status = int(parser.get().result_int());
    copy_headers(parser.get().base(), out);
    out.body = std::move(parser.get().body());
    return out;
  } catch (const boost::system::system_error& e) {
    throw ConnectionError(base_url() + std::string(target) + ": " + e.code().message());
  }
}

HttpResponse HttpClient::stream(std::string_view target,
                                const std::function<bool(std::string_view)>& on_bytes) const {
  Connection c(host_, port_, timeout_s_);
  HttpResponse out;
  try {
    c.send("GET", target, host_, {}, {});
    beast::flat_buffer buffer;
    http::response_parser<http::buffer_body> parser;
    parser.body_limit(boost::none);
    http::read_header(c.stream, buffer, parser);
    out.status = int(parser.get().result_int());
    copy_headers(parser.get().base(), out);
    char chunk[64 * 1024];
    while (!parser.is_done()) {
      parser.get().body().data = chunk;
      parser.get().body().size = sizeof chunk;
      beast::error_code ec;
      http::read_some(c.stream, buffer, parser, ec);
      if (ec && ec != http::error::need_buffer && ec != http::error::partial_message &&
          ec != net::error::eof)
        throw boost::system::system_error(ec);
      std::size_t got = sizeof chunk - parser.get().body().size;
      if (got && !on_bytes(std::string_view(chunk, got))) break;
      if (ec == net::error::eof || ec == http::error::partial_message) break;
      // Each piece of a stream is written in time; only the silence between them counts.
      c.stream.expires_after(std::chrono::milliseconds(long(timeout_s_ * 1000)));
    }
  } catch (const boost::system::system_error& e) {
    throw ConnectionError(base_url() + std::string(target) + ": " + e.code().message());
  }
  return out;
}

std::pair<std::string, unsigned short> parse_server_url(std::string_view url) {
  if (url.starts_with("http://")) url.remove_prefix(7);
  while (url.ends_with("/")) url.remove_suffix(1);
  auto colon = url.rfind(':');
  unsigned port = 0;
  if (colon == std::string_view::npos || colon == 0) throw std::invalid_argument("no port");
  auto [end, ec] = std::from_chars(url.data() + colon + 1, url.data() + url.size(), port);
  if (ec != std::errc() || end != url.data() + url.size() || port == 0 || port > 65535)
    throw std::invalid_argument("\"" + std::string(url) + "\" is not host:port");
  return {std::string(url.substr(0, colon)), static_cast<unsigned short>(port)};
}

}  // namespace bumprad
