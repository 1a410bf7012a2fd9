// One HTTP connection, after Boost.Beast's own server examples: reads requests with a body
// limit and a deadline, answers them through the Api, and keeps a stream of a job's steps
// going for as long as the viewer stays, re-arming the deadline before every write.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <stop_token>
#include <string>

#include <boost/asio/steady_timer.hpp>
#include <boost/asio/thread_pool.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include "common/stopwatch.h"
#include "server/api.h"
#include "server/step_stream.h"

namespace bumprad {

namespace beast = boost::beast;
namespace net = boost::asio;

// What every connection shares.
struct SessionContext {
  Api& api;
  Metrics& metrics;
  net::thread_pool& parse_pool;   // request bodies parsed and validated, off the network threads
  net::thread_pool& render_pool;  // re-texturing
  std::chrono::seconds read_timeout{30};
  std::chrono::seconds heartbeat{15};
  std::atomic<int> busy{0};         // requests between read and written, streams until they end
  std::atomic<int> deferred{0};     // re-textures waiting for or on the render pool
  int max_deferred = 16;            // more are refused with 503, so bodies cannot pile up
  std::atomic<int> connections{0};  // open now
  int max_connections = 512;        // more are answered 503 and closed
  std::stop_source shutdown{};      // stopped on SIGINT/SIGTERM
};

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(net::ip::tcp::socket&& socket, SessionContext& context);
  ~HttpSession();
  void run();

 private:
  void read();
  void on_header(beast::error_code ec);  // answers Expect: 100-continue, then read_body()
  void read_body();
  void on_read(beast::error_code ec);
  void defer(DeferredRequest deferred);
  // Stops `stop` if the client hangs up while its request is being worked on.
  void watch_for_hangup(std::stop_source stop);
  void write(Response response);
  void count_request(int status);  // the log line and the metrics
  void not_busy();                 // the answer is written: shutdown need not wait for it
  void close();

  void start_stream(StreamRequest request);
  void pump();  // writes what the stream has to catch up on, if not writing already
  void write_stream(std::string bytes);
  void arm_heartbeat();
  void end_stream();
  bool shutting_down() const;

  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  SessionContext& context_;

  // The request being answered, for the log and the metrics.
  std::string method_, target_, route_;
  Clock::time_point started_;
  bool busy_ = false;

  struct Watch {
    std::shared_ptr<Job> job;
    StepStream stream;
    int watcher = -1;
    bool writing = false, pending = false;
    std::shared_ptr<std::string> out;
  };
  std::optional<Watch> watch_;
  net::steady_timer heartbeat_;
};

}  // namespace bumprad
