#include "cli/serve_command.h"

#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>

#include "cli/command.h"
#include "common/args.h"
#include "server/server.h"

namespace bumprad {
namespace {

constexpr const char* kUsage =
    "usage: bumprad serve [--bind ADDR] [--port P] [--data-dir DIR | --store URL] [--workers N]\n"
    "                     [--max-queue Q] [--assets DIR] [--max-image-memory B]\n"
    "                     [--keep-steps K] [--max-jobs J]\n"
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
    "  --max-image-memory 2G  what one scene's images may take decoded, checked from their\n"
    "                       headers before decoding (each image is also limited to 8192^2)\n"
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
    "                      [--max-image-memory B]\n"
    "                      [--job-timeout S] [--keep-steps K] [--max-jobs J] [--max-bytes B]\n"
    "                      [--lease S] [--max-attempts N]\n"
    "  Solves the jobs that `bumprad serve --store` nodes take, with the same options\n"
    "  (bumprad serve --help); --workers defaults to 1. SIGINT or SIGTERM returns running\n"
    "  jobs to the queue.\n";

// The flags serve and worker share; `workers` is left empty when not given.
ArgParser node_flags(NodeOptions& o, std::optional<int>& workers) {
  ArgParser p;
  p.custom({"--store"},
           [&o](std::string_view flag, std::string_view v) {
             if (v.empty())
               throw UsageError(std::string(flag) + ": empty; name a database (postgresql://...)");
             o.store_url = v;
           })
      .custom({"--data-dir"}, [&o](std::string_view, std::string_view v) { o.data_dir = v; })
      .integer({"--workers"}, workers, 0, 64)
      .integer({"--max-queue"}, o.store.max_queue, 1, 1'000'000'000)
      .custom({"--assets"},
              [&o](std::string_view, std::string_view v) {
                for (ImageFiles* f : {&o.api.files, &o.runner.files}) {
                  f->access = ImageFiles::Access::Sandbox;
                  f->root = std::string(v);
                }
              })
      .custom({"--max-image-memory"},
              [&o](std::string_view flag, std::string_view v) {
                o.api.files.max_image_bytes = o.runner.files.max_image_bytes =
                    std::size_t(parse_integer(flag, v, 1 << 20, INT64_MAX, true));
              })
      .integer({"--keep-steps"}, o.store.keep_steps, 1, 100'000)
      .integer({"--max-jobs"}, o.store.retention.max_jobs, 1, 1'000'000'000)
      .integer({"--max-bytes"}, o.store.retention.max_bytes, 1, INT64_MAX, true)
      .integer({"--lease"}, o.postgres.lease_s, 1, 86'400)
      .integer({"--max-attempts"}, o.postgres.max_attempts, 1, 100)
      .integer({"--job-timeout"}, o.runner.job_timeout_s, 1, 1'000'000'000);
  return p;
}

ServerOptions parse_serve_args(std::span<const std::string_view> args) {
  ServerOptions o;
  std::optional<int> workers;
  ArgParser p = node_flags(o.node, workers);
  p.text({"--bind"}, o.bind)
      .integer({"--port"}, o.port, 0, 65535)
      .integer({"--max-retextures"}, o.max_retextures, 1, 4096)
      .integer({"--body-limit"}, o.node.api.body_limit, 1024, INT64_MAX, true)
      .integer({"--max-connections"}, o.max_connections, 1, 1'000'000)
      .integer({"--max-job-seconds"}, o.node.api.max_job_seconds, 1, 1'000'000'000)
      .integer({"--max-retexture-seconds"}, o.node.api.max_retexture_seconds, 1, 1'000'000'000)
      .integer({"--retexture-timeout"}, o.node.api.retexture_timeout_s, 1, 1'000'000'000)
      .parse(args);
  if (o.node.store_url.empty() && workers == 0)
    throw UsageError("--workers: at least 1 without --store (nothing else would solve)");
  o.node.workers = workers.value_or(o.node.store_url.empty() ? 1 : 0);
  return o;
}

NodeOptions parse_worker_args(std::span<const std::string_view> args) {
  NodeOptions o;
  std::optional<int> workers;
  ArgParser p = node_flags(o, workers);
  for (const char* serve_only :
       {"--bind", "--port", "--max-retextures", "--body-limit", "--max-connections",
        "--max-job-seconds", "--max-retexture-seconds", "--retexture-timeout"})
    p.custom({serve_only}, [](std::string_view flag, std::string_view) {
      throw UsageError(std::string(flag) + " is for bumprad serve; a worker serves no HTTP");
    });
  p.parse(args);
  if (o.store_url.empty())
    throw UsageError("--store postgresql://... is required: a worker shares its store");
  o.workers = workers.value_or(1);
  if (o.workers < 1) throw UsageError("--workers: at least 1");
  return o;
}

}  // namespace

int serve_command(std::span<const std::string_view> args) {
  return run_command("serve", kUsage, args, [](std::span<const std::string_view> a) {
    return run_server(parse_serve_args(a));
  });
}

int worker_command(std::span<const std::string_view> args) {
  return run_command("worker", kWorkerUsage, args, [](std::span<const std::string_view> a) {
    return run_worker(parse_worker_args(a));
  });
}

}  // namespace bumprad
