#include "server/server.h"

#include <pthread.h>

#include <csignal>
#include <cstdio>
#include <thread>
#include <vector>

#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>

#include "server/listener.h"

namespace bumprad {

int run_server(const ServerOptions& options) {
  Node node(options.node);
  net::thread_pool parse_pool(2);
  net::thread_pool render_pool(2);
  SessionContext context{node.api, node.metrics, parse_pool, render_pool};
  context.max_deferred = options.max_retextures;
  context.max_connections = options.max_connections;

  net::io_context ioc;
  auto address = net::ip::make_address(options.bind);
  auto listener =
      std::make_shared<Listener>(ioc, net::ip::tcp::endpoint{address, options.port}, context);
  listener->run();
  std::printf("bumprad: listening on http://%s:%u (%s)\n", options.bind.c_str(),
              unsigned(listener->port()),
              options.node.store_url.empty() ? ("data in " + options.node.data_dir.string()).c_str()
                                             : "jobs in PostgreSQL");
  std::fflush(stdout);

  // Shutdown: stop accepting; stop the solver (running jobs become interrupted, which ends
  // their streams); let answers in flight finish within the grace period; then stop.
  net::signal_set signals(ioc, SIGINT, SIGTERM);
  net::steady_timer grace(ioc);
  auto deadline = std::chrono::steady_clock::now();
  std::thread stopper;
  std::function<void()> wait_for_idle = [&] {
    if (context.busy == 0 || std::chrono::steady_clock::now() >= deadline) return ioc.stop();
    grace.expires_after(std::chrono::milliseconds(20));
    grace.async_wait([&](beast::error_code) { wait_for_idle(); });
  };
  signals.async_wait([&](beast::error_code ec, int signal) {
    if (ec) return;
    std::fprintf(stderr, "bumprad: signal %d, shutting down\n", signal);
    context.shutdown.request_stop();  // re-textures stop within a row
    listener->stop();
    stopper = std::thread([&] {  // waiting for the workers must not block the network
      node.shutdown();
      net::post(ioc, [&] {
        deadline = std::chrono::steady_clock::now() + options.grace;
        wait_for_idle();
      });
    });
  });

  std::vector<std::thread> threads;
  for (int i = 1; i < options.io_threads; ++i) threads.emplace_back([&] { ioc.run(); });
  ioc.run();
  for (auto& t : threads) t.join();
  if (stopper.joinable()) stopper.join();
  node.shutdown();
  parse_pool.join();
  render_pool.join();
  std::fprintf(stderr, "bumprad: stopped\n");
  return 0;
}

int run_worker(const NodeOptions& options) {
  // Blocked before the node starts its threads, so that only sigwait below takes them.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  Node node(options);
  std::printf("bumprad: worker ready (%d solver threads)\n", options.workers);
  std::fflush(stdout);
  int signal = 0;
  sigwait(&signals, &signal);
  std::fprintf(stderr, "bumprad: signal %d, releasing running jobs\n", signal);
  node.shutdown();
  std::fprintf(stderr, "bumprad: stopped\n");
  return 0;
}

}  // namespace bumprad
