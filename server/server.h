// `bumprad serve`: the HTTP render service (a node, node.h, behind a listener), and
// `bumprad worker`: a node that only solves. Both run until SIGINT or SIGTERM, then shut
// down gracefully.
#pragma once

#include <chrono>
#include <filesystem>
#include <string>

#include "server/api.h"
#include "server/node.h"

namespace bumprad {

struct ServerOptions {
  std::string bind = "127.0.0.1";
  unsigned short port = 8080;  // 0: any free port (printed at start)
  int io_threads = 2;
  std::chrono::milliseconds grace{3000};  // for answers in flight at shutdown
  int max_retextures = 16;                // waiting to render before 503
  int max_connections = 512;              // open at once; more get 503
  NodeOptions node;
};

// Prints "bumprad: listening on http://HOST:PORT" once ready. Returns the exit status.
int run_server(const ServerOptions& options);

// `bumprad worker`: a node with solver workers and no HTTP, on a shared store, until
// SIGINT or SIGTERM; then running jobs go back to the queue. Prints "bumprad: worker
// ready" once it claims.
int run_worker(const NodeOptions& options);

}  // namespace bumprad
