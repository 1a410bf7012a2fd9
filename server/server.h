// `bumprad serve`: the HTTP render service put together (job store, queue and workers,
// API, listener), running until SIGINT or SIGTERM, then shutting down gracefully.
#pragma once

#include <chrono>
#include <filesystem>
#include <string>

#include "server/api.h"
#include "server/job_queue.h"

namespace bumprad {

struct ServerOptions {
  std::string bind = "127.0.0.1";
  unsigned short port = 8080;  // 0: any free port (printed at start)
  std::filesystem::path data_dir = "bumprad-data";
  int io_threads = 2;
  std::chrono::milliseconds grace{3000};  // for answers in flight at shutdown
  int max_retextures = 16;                // waiting to render before 503
  int max_connections = 512;              // open at once; more get 503
  ApiLimits api;
  QueueOptions queue;
};

// Prints "bumprad: listening on http://HOST:PORT" once ready. Returns the exit status.
int run_server(const ServerOptions& options);

}  // namespace bumprad
