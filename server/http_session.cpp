#include "server/http_session.h"

#include <cstdio>

#include <boost/asio/post.hpp>

namespace bumprad {

HttpSession::HttpSession(net::ip::tcp::socket&& socket, SessionContext& context)
    : stream_(std::move(socket)), context_(context), heartbeat_(stream_.get_executor()) {}

HttpSession::~HttpSession() {
  if (watch_ && watch_->watcher >= 0) watch_->job->unwatch(watch_->watcher);
  if (busy_) --context_.busy;
}

void HttpSession::run() {
  net::post(stream_.get_executor(), [self = shared_from_this()] { self->read(); });
}

void HttpSession::read() {
  if (context_.stopping) return close();
  parser_.emplace();
  parser_->body_limit(context_.api.body_limit());
  parser_->header_limit(16 * 1024);
  stream_.expires_after(context_.read_timeout);  // a deadline for the whole request
  http::async_read(
      stream_, buffer_, *parser_,
      [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
}

void HttpSession::on_read(beast::error_code ec) {
  if (ec == http::error::end_of_stream || ec == beast::error::timeout ||
      ec == net::error::operation_aborted || ec == net::error::connection_reset)
    return close();
  started_ = Clock::now();
  busy_ = true;
  ++context_.busy;
  const Request& request = parser_->get();
  method_ = std::string(request.method_string());
  target_ = std::string(request.target());
  if (ec) {
    // The request cannot be read whole: answer, then close, since the rest of it may still
    // be arriving.
    Request head;
    head.version(request.version() ? request.version() : 11);
    head.keep_alive(false);
    route_ = "(unreadable)";
    if (ec == http::error::body_limit)
      return write(problem(
          head, http::status::payload_too_large, "Body too large",
          "request bodies are limited to " + std::to_string(context_.api.body_limit()) + " bytes"));
    if (ec == http::error::header_limit)
      return write(problem(head, http::status::request_header_fields_too_large, "Headers too large",
                           "request headers are limited to 16384 bytes"));
    return write(problem(head, http::status::bad_request, "Bad request",
                         "unreadable HTTP request: " + ec.message()));
  }
  Routed routed = context_.api.handle(request);
  route_ = routed.route;
  if (auto* response = std::get_if<Response>(&routed.action)) return write(std::move(*response));
  if (auto* stream = std::get_if<StreamRequest>(&routed.action))
    return start_stream(std::move(*stream));
  auto& deferred = std::get<DeferredRequest>(routed.action);
  if (++context_.deferred > context_.max_deferred) {
    --context_.deferred;
    Response busy = problem(request, http::status::service_unavailable, "Busy",
                            std::to_string(context_.max_deferred) +
                                " re-textures are already waiting to render; try again shortly");
    busy.set(http::field::retry_after, "1");
    return write(std::move(busy));
  }
  net::post(context_.render_pool, [self = shared_from_this(), work = std::move(deferred.work)] {
    Response response = work();
    --self->context_.deferred;
    net::post(self->stream_.get_executor(),
              [self, r = std::move(response)]() mutable { self->write(std::move(r)); });
  });
}

void HttpSession::write(Response response) {
  auto res = std::make_shared<Response>(std::move(response));
  if (context_.stopping) res->keep_alive(false);
  stream_.expires_after(context_.read_timeout);
  http::async_write(stream_, *res,
                    [self = shared_from_this(), res](beast::error_code ec, std::size_t) {
                      self->finish_request(res->result_int());
                      if (ec || !res->keep_alive()) return self->close();
                      self->read();
                    });
}

void HttpSession::finish_request(int status) {
  double seconds = seconds_since(started_);
  context_.metrics.count_request(method_, route_, status, seconds);
  std::fprintf(stderr, "%s %s %d %.1f ms\n", method_.c_str(), target_.c_str(), status,
               1000 * seconds);
  if (busy_) --context_.busy;
  busy_ = false;
}

void HttpSession::close() {
  heartbeat_.cancel();
  beast::error_code ignored;
  stream_.socket().shutdown(net::ip::tcp::socket::shutdown_send, ignored);
}

void HttpSession::start_stream(StreamRequest request) {
  watch_.emplace(Watch{request.job, StepStream(request.kind), -1, false, false, nullptr});
  auto header = std::make_shared<http::response<http::empty_body>>(http::status::ok,
                                                                   parser_->get().version());
  header->set(http::field::server, "bumprad");
  header->set(http::field::content_type, watch_->stream.content_type());
  header->set(http::field::cache_control, "no-cache");
  header->set("X-Accel-Buffering", "no");
  header->keep_alive(false);  // the body ends when the connection closes
  auto serializer = std::make_shared<http::response_serializer<http::empty_body>>(*header);
  std::weak_ptr<HttpSession> weak = shared_from_this();
  auto executor = stream_.get_executor();
  watch_->watcher = request.job->watch([weak, executor] {
    net::post(executor, [weak] {
      if (auto self = weak.lock()) self->pump();
    });
  });
  watch_->writing = true;
  stream_.expires_after(context_.read_timeout);
  http::async_write_header(
      stream_, *serializer,
      [self = shared_from_this(), header, serializer](beast::error_code ec, std::size_t) {
        self->watch_->writing = false;
        if (ec) return self->end_stream();
        self->pump();  // the first event at once
      });
}

void HttpSession::pump() {
  if (!watch_) return;
  if (watch_->writing) {
    watch_->pending = true;
    return;
  }
  std::string bytes = watch_->stream.catch_up(watch_->job->view());
  if (!bytes.empty()) return write_stream(std::move(bytes));
  if (watch_->stream.finished() || context_.stopping) return end_stream();
  arm_heartbeat();
}

void HttpSession::write_stream(std::string bytes) {
  heartbeat_.cancel();
  watch_->writing = true;
  watch_->pending = false;
  watch_->out = std::make_shared<std::string>(std::move(bytes));
  stream_.expires_after(context_.read_timeout);  // re-armed per write: a stream has no end
  net::async_write(stream_, net::buffer(*watch_->out),
                   [self = shared_from_this()](beast::error_code ec, std::size_t) {
                     self->watch_->writing = false;
                     if (ec) return self->end_stream();
                     if (self->watch_->stream.finished()) return self->end_stream();
                     self->pump();
                   });
}

void HttpSession::arm_heartbeat() {
  std::string beat = watch_->stream.heartbeat();
  heartbeat_.expires_after(context_.heartbeat);
  heartbeat_.async_wait([self = shared_from_this(), beat](beast::error_code ec) {
    if (ec || !self->watch_ || self->watch_->writing) return;
    if (self->context_.stopping) return self->end_stream();
    if (beat.empty()) return self->arm_heartbeat();
    self->write_stream(beat);
  });
}

void HttpSession::end_stream() {
  if (watch_->watcher < 0) return;  // ended already
  watch_->job->unwatch(watch_->watcher);
  watch_->watcher = -1;
  finish_request(200);
  close();
}

}  // namespace bumprad
