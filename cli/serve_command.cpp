#include "cli/serve_command.h"

#include <algorithm>
#include <charconv>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>

#include "cli/usage_error.h"
#include "server/server.h"

namespace bumprad {
namespace {

constexpr const char* kUsage =
    "usage: bumprad serve [--bind ADDR] [--port P] [--data-dir DIR | --store URL] [--workers N]\n"
    "                     [--max-queue Q] [--assets DIR] [--keep-steps K] [--max-jobs J]\n"
    "                     [--max-bytes B] [--body-limit B] [--max-retextures R]\n"
    "                     [--max-connections C] [--max-job-seconds S]\n"
    "                     [--max-retexture-seconds S] [--job-timeout S] [--retexture-timeout S]\n"
    "                     [--lease S] [--max-attempts N]\n"
    "  --bind 127.0.0.1     address to listen on (0.0.0.0 for every interface)\n"
    "  --port 8080          0 picks a free port, printed at start\n"
    "  --data-dir DIR       jobs, solutions and images (default ./bumprad-data)\n"
    "  --store URL          keep them in PostgreSQL instead (postgresql://...), shared with\n"
    "                       other API nodes and `bumprad worker`s\n"
    "  --workers 1          jobs solved at once (with --store, default 0: an API-only node)\n"
    "  --max-queue 16       waiting jobs before POST /v1/jobs answers 429\n"
    "  --assets DIR         image files scenes may name (default: none may be named)\n"
    "  --keep-steps 64      newest step previews kept per job\n"
    "  --max-jobs 500       finished jobs kept (least recently used evicted first)\n"
    "  --max-bytes 4G       their files in all (suffixes K, M, G)\n"
    "  --body-limit 8M      largest request body accepted\n"
    "  --max-retextures 16  re-textures waiting to render before 503\n"
    "  --max-connections 512       open connections; more are answered 503 and closed\n"
    "  --max-job-seconds 600       a job's estimated solve and render time; more is 422\n"
    "  --max-retexture-seconds 30  a re-texture's estimated render time; more is 422\n"
    "  --job-timeout 3600          wall-clock seconds a job may run, then it fails\n"
    "  --retexture-timeout 60      wall-clock seconds a re-texture may render, then 503\n"
    "  --lease 30           with --store: seconds a worker may go silent before its job is\n"
    "                       claimed again elsewhere (renewed at every refinement step)\n"
    "  --max-attempts 3     with --store: claims of one job before it fails for good\n";

constexpr const char* kWorkerUsage =
    "usage: bumprad worker --store postgresql://... [--workers N] [--assets DIR]\n"
    "                      [--job-timeout S] [--keep-steps K] [--max-jobs J] [--max-bytes B]\n"
    "                      [--lease S] [--max-attempts N]\n"
    "  Solves the jobs that `bumprad serve --store` nodes take, with the same options\n"
    "  (bumprad serve --help); --workers defaults to 1. SIGINT or SIGTERM returns running\n"
    "  jobs to the queue.\n";

// A count or size with an optional K/M/G suffix, at least `min`.
std::uintmax_t parse_amount(std::string_view flag, std::string_view text, std::uintmax_t min,
                            bool suffixes) {
  std::uintmax_t value = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  std::string_view rest(end, std::size_t(text.data() + text.size() - end));
  int shift = rest == "K" ? 10 : rest == "M" ? 20 : rest == "G" ? 30 : rest.empty() ? 0 : -1;
  if (ec != std::errc() || shift < 0 || (shift && !suffixes) || value > (UINTMAX_MAX >> shift) ||
      (value << shift) < min)
    throw UsageError(std::string(flag) + ": \"" + std::string(text) + "\" is not " +
                     (suffixes ? "a size" : "a whole number") + " of at least " +
                     std::to_string(min));
  return value << shift;
}

ServerOptions parse_args(std::span<const std::string_view> args) {
  ServerOptions o;
  std::optional<int> workers;
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string_view flag = args[i];
    if (i + 1 >= args.size())
      throw UsageError("unknown option or missing value: " + std::string(flag));
    std::string_view v = args[++i];
    if (flag == "--bind")
      o.bind = v;
    else if (flag == "--port") {
      std::uintmax_t port = parse_amount(flag, v, 0, false);
      if (port > 65535) throw UsageError("--port: at most 65535");
      o.port = static_cast<unsigned short>(port);
    } else if (flag == "--store")
      o.node.store_url = v;
    else if (flag == "--data-dir")
      o.node.data_dir = v;
    else if (flag == "--workers")
      workers = int(std::min<std::uintmax_t>(64, parse_amount(flag, v, 0, false)));
    else if (flag == "--max-queue")
      o.node.store.max_queue = parse_amount(flag, v, 1, false);
    else if (flag == "--assets")
      o.node.api.files = o.node.runner.files = ImageFiles::sandbox(v);
    else if (flag == "--keep-steps")
      o.node.store.keep_steps =
          int(std::min<std::uintmax_t>(100000, parse_amount(flag, v, 1, false)));
    else if (flag == "--max-jobs")
      o.node.store.retention.max_jobs = parse_amount(flag, v, 1, false);
    else if (flag == "--max-bytes")
      o.node.store.retention.max_bytes = parse_amount(flag, v, 1, true);
    else if (flag == "--max-retextures")
      o.max_retextures = int(std::min<std::uintmax_t>(4096, parse_amount(flag, v, 1, false)));
    else if (flag == "--body-limit")
      o.node.api.body_limit = parse_amount(flag, v, 1024, true);
    else if (flag == "--max-connections")
      o.max_connections = int(std::min<std::uintmax_t>(1'000'000, parse_amount(flag, v, 1, false)));
    else if (flag == "--max-job-seconds")
      o.node.api.max_job_seconds = double(parse_amount(flag, v, 1, false));
    else if (flag == "--max-retexture-seconds")
      o.node.api.max_retexture_seconds = double(parse_amount(flag, v, 1, false));
    else if (flag == "--lease")
      o.node.postgres.lease_s = double(parse_amount(flag, v, 1, false));
    else if (flag == "--max-attempts")
      o.node.postgres.max_attempts =
          int(std::min<std::uintmax_t>(100, parse_amount(flag, v, 1, false)));
    else if (flag == "--job-timeout")
      o.node.runner.job_timeout_s = double(parse_amount(flag, v, 1, false));
    else if (flag == "--retexture-timeout")
      o.node.api.retexture_timeout_s = double(parse_amount(flag, v, 1, false));
    else
      throw UsageError("unknown option " + std::string(flag));
  }
  if (o.node.store_url.empty() && workers == 0)
    throw UsageError("--workers: at least 1 without --store (nothing else would solve)");
  o.node.workers = workers.value_or(o.node.store_url.empty() ? 1 : 0);
  return o;
}

}  // namespace

int serve_command(std::span<const std::string_view> args) {
  if (args.size() == 1 && (args[0] == "--help" || args[0] == "-h")) {
    std::cout << kUsage;
    return 0;
  }
  ServerOptions options;
  try {
    options = parse_args(args);
  } catch (const UsageError& e) {
    std::cerr << "bumprad serve: " << e.what() << "\n" << kUsage;
    return 2;
  }
  try {
    return run_server(options);
  } catch (const std::exception& e) {
    std::cerr << "bumprad serve: " << e.what() << "\n";
    return 1;
  }
}

int worker_command(std::span<const std::string_view> args) {
  if (args.size() == 1 && (args[0] == "--help" || args[0] == "-h")) {
    std::cout << kWorkerUsage;
    return 0;
  }
  NodeOptions options;
  try {
    for (std::size_t i = 0; i < args.size(); i += 2)
      if (args[i] == "--bind" || args[i] == "--port" || args[i] == "--data-dir" ||
          args[i].starts_with("--max-re") || args[i] == "--body-limit" ||
          args[i] == "--max-connections" || args[i] == "--max-job-seconds")
        throw UsageError(std::string(args[i]) + " is for bumprad serve; a worker serves no HTTP");
    ServerOptions parsed = parse_args(args);
    if (parsed.node.store_url.empty())
      throw UsageError("--store postgresql://... is required: a worker shares its store");
    options = parsed.node;
    if (std::find(args.begin(), args.end(), "--workers") == args.end()) options.workers = 1;
    if (options.workers < 1) throw UsageError("--workers: at least 1");
  } catch (const UsageError& e) {
    std::cerr << "bumprad worker: " << e.what() << "\n" << kWorkerUsage;
    return 2;
  }
  try {
    return run_worker(options);
  } catch (const std::exception& e) {
    std::cerr << "bumprad worker: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace bumprad
