#include "server/http_session.h"

#include <sys/socket.h>

#include <cerrno>
#include <cstdio>

#include <boost/asio/post.hpp>

namespace bumprad {

HttpSession::HttpSession(net::ip::tcp::socket&& socket, SessionContext& context)
    : stream_(std::move(socket)), context_(context), heartbeat_(stream_.get_executor()) {
  ++context_.connections;
}

HttpSession::~HttpSession() {
  if (watch_ && watch_->watcher >= 0) watch_->job->unwatch(watch_->watcher);
  if (busy_) --context_.busy;
  --context_.connections;
}

void HttpSession::run() {
  net::post(stream_.get_executor(), [self = shared_from_this()] {
    if (self->context_.connections <= self->context_.max_connections) return self->read();
    // Over the cap: say so and close, without reading the request.
    self->started_ = Clock::now();
    self->method_ = self->target_ = "-";
    self->route_ = "(too many connections)";
    Request head;
    head.keep_alive(false);
    Response busy =
        problem(head, http::status::service_unavailable, "Too many connections",
                "this server takes at most " + std::to_string(self->context_.max_connections) +
                    " connections at once; try again shortly");
    busy.set(http::field::retry_after, "1");
    self->write(std::move(busy));
  });
}

void HttpSession::read() {
  if (context_.shutdown.stop_requested()) return close();
  parser_.emplace();
  parser_->body_limit(context_.api.limits().body_limit);
  parser_->header_limit(16 * 1024);
  stream_.expires_after(context_.read_timeout);  // a deadline for the whole request
  http::async_read_header(
      stream_, buffer_, *parser_,
      [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_header(ec); });
}

// A client that sends `Expect: 100-continue` (curl does for bodies over 1 KiB) waits for a
// 100 before its body, a second by default if none comes (RFC 9110 10.1.1). The header was
// read whole and its Content-Length is within the body limit (else ec is body_limit and the
// 413 goes out before any of the body is read).
void HttpSession::on_header(beast::error_code ec) {
  const auto& head = parser_->get();
  if (ec) return on_read(ec);
  if (parser_->is_done() || !beast::iequals(head[http::field::expect], "100-continue"))
    return read_body();
  auto go_on =
      std::make_shared<http::response<http::empty_body>>(http::status::continue_, head.version());
  http::async_write(stream_, *go_on,
                    [self = shared_from_this(), go_on](beast::error_code failed, std::size_t) {
                      if (failed) return self->close();
                      self->read_body();
                    });
}

void HttpSession::read_body() {
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
      return write(problem(head, http::status::payload_too_large, "Body too large",
                           "request bodies are limited to " +
                               std::to_string(context_.api.limits().body_limit) + " bytes"));
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
  defer(std::move(std::get<DeferredRequest>(routed.action)));
}

void HttpSession::defer(DeferredRequest deferred) {
  const bool render = deferred.pool == DeferredRequest::Pool::Render;
  if (render && ++context_.deferred > context_.max_deferred) {
    --context_.deferred;
    Response busy = problem(parser_->get(), http::status::service_unavailable, "Busy",
                            std::to_string(context_.max_deferred) +
                                " re-textures are already waiting to render; try again shortly");
    busy.set(http::field::retry_after, "1");
    return write(std::move(busy));
  }
  std::stop_source stop;
  if (render) watch_for_hangup(stop);
  net::post(render ? context_.render_pool : context_.parse_pool,
            [self = shared_from_this(), work = std::move(deferred.work),
             request = parser_->release(), stop, render]() mutable {
              std::stop_callback on_shutdown(self->context_.shutdown.get_token(),
                                             [stop]() mutable { stop.request_stop(); });
              Response response = work(request, stop);
              if (render) --self->context_.deferred;
              net::post(self->stream_.get_executor(), [self, r = std::move(response)]() mutable {
                beast::error_code ignored;
                self->stream_.socket().cancel(ignored);  // the hang-up watch
                self->write(std::move(r));
              });
            });
}

void HttpSession::watch_for_hangup(std::stop_source stop) {
  stream_.socket().async_wait(net::socket_base::wait_read, [self = shared_from_this(),
                                                            stop](beast::error_code ec) mutable {
    if (ec == net::error::operation_aborted) return;  // answered first
    // Readable: the end of the stream (or an error) is a hang-up; bytes of a pipelined
    // next request are not, and they stay unread for later.
    char byte;
    ssize_t n = ::recv(self->stream_.socket().native_handle(), &byte, 1, MSG_PEEK | MSG_DONTWAIT);
    if (ec || n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) stop.request_stop();
  });
}

void HttpSession::write(Response response) {
  auto res = std::make_shared<Response>(std::move(response));
  if (context_.shutdown.stop_requested()) res->keep_alive(false);
  // Counted before it is sent: a client that has its answer sees it in /metrics.
  count_request(res->result_int());
  stream_.expires_after(context_.read_timeout);
  http::async_write(stream_, *res,
                    [self = shared_from_this(), res](beast::error_code ec, std::size_t) {
                      self->not_busy();
                      if (ec || !res->keep_alive()) return self->close();
                      self->read();
                    });
}

void HttpSession::count_request(int status) {
  double seconds = seconds_since(started_);
  context_.metrics.count_request(method_, route_, status, seconds);
  std::fprintf(stderr, "%s %s %d %.1f ms\n", method_.c_str(), valid_utf8(target_).c_str(), status,
               1000 * seconds);
}

void HttpSession::not_busy() {
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
  if (watch_->stream.finished() || shutting_down()) return end_stream();
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
    if (self->shutting_down()) return self->end_stream();
    if (beat.empty()) return self->arm_heartbeat();
    self->write_stream(beat);
  });
}

bool HttpSession::shutting_down() const {
  // A running job's stream waits for the job's own end (its worker stops within a shot and
  // says interrupted); the grace period bounds the wait.
  return context_.shutdown.stop_requested() &&
         watch_->job->view().record.state != JobState::Running;
}

void HttpSession::end_stream() {
  if (watch_->watcher < 0) return;  // ended already
  watch_->job->unwatch(watch_->watcher);
  watch_->watcher = -1;
  count_request(200);
  not_busy();
  close();
}

}  // namespace bumprad
