// The real server for the integration tests: `bumprad serve` started as its own process on
// an ephemeral loopback port, with a data directory that outlives it for restart tests.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

#include "clients/http_client.h"

namespace bumprad::test {

class ServerProcess {
 public:
  // Starts `bumprad serve --port 0 --data-dir DATA ARGS...` and waits until it listens;
  // `prefix` runs it through another program (e.g. {"prlimit", "--nofile=64"}). With
  // `command` "worker": `bumprad worker ARGS...`, until it says it is ready (no port; its
  // log is DATA.log).
  ServerProcess(const std::filesystem::path& data_dir, const std::vector<std::string>& args = {},
                const std::vector<std::string>& prefix = {}, const std::string& command = "serve");
  ~ServerProcess();  // SIGKILL if it still runs
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  unsigned short port() const { return port_; }
  pid_t pid() const { return pid_; }
  HttpClient client(double timeout_s = 60) const {
    return HttpClient("127.0.0.1", port_, timeout_s);
  }
  // SIGTERM, then the exit status once it has stopped.
  int terminate();
  void kill_hard();         // SIGKILL: no chance to save anything
  std::string log() const;  // what it wrote to stderr

 private:
  pid_t pid_ = -1;
  int stdout_fd_ = -1;
  unsigned short port_ = 0;
  std::filesystem::path log_;
};

// A small room with a light and a wrinkled box, cheap enough to solve in a test: JSON text.
// `endless` does not converge (unshot fraction 0) and takes about a minute (300,000 shots;
// a million would be over the server's default cost limit): a job to cancel or kill.
std::string small_scene_json(int max_shots, bool endless = false);
// A lamp 1 m square 10 cm over a white floor of the same size, each `elements` x
// `elements` (in patches of `patch_elements` a side, where given), two shots: slow by
// construction when large (a long near field, or a long set-up), whatever the machine.
std::string facing_quads_json(int elements, int patch_elements = 0);
// {"scene": small_scene_json(...), ...extra request keys}
std::string small_job_json(int max_shots, int preview_every, bool endless = false);

// Polls the job until `done(state)` or `seconds` pass; returns its last JSON.
std::string wait_for_job(const HttpClient& client, const std::string& id,
                         const std::vector<std::string>& states, double seconds = 60);

}  // namespace bumprad::test
