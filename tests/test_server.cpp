#include "tests/test_server.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>

extern char** environ;

namespace bumprad::test {

using json = nlohmann::json;

ServerProcess::ServerProcess(const std::filesystem::path& data_dir,
                             const std::vector<std::string>& args,
                             const std::vector<std::string>& prefix, const std::string& command)
    : log_(data_dir.string() + ".log") {
  std::vector<std::string> argv = prefix;
  argv.push_back(BUMPRAD_BIN);
  argv.push_back(command);
  if (command == "serve")
    for (std::string a :
         {std::string("--port"), std::string("0"), std::string("--data-dir"), data_dir.string()})
      argv.push_back(a);
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> c_argv;
  for (auto& a : argv) c_argv.push_back(a.data());
  c_argv.push_back(nullptr);

  int out[2];
  if (pipe(out) != 0) throw std::runtime_error("pipe failed");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, out[0]);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log_.c_str(),
                                   O_WRONLY | O_CREAT | O_APPEND, 0644);
  int rc = posix_spawnp(&pid_, argv[0].c_str(), &actions, nullptr, c_argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(out[1]);
  stdout_fd_ = out[0];
  if (rc != 0) throw std::runtime_error("cannot start " + argv[0]);

  // "bumprad: listening on http://127.0.0.1:PORT (...)"
  std::string line;
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (line.find('\n') == std::string::npos) {
    pollfd p{stdout_fd_, POLLIN, 0};
    if (std::chrono::steady_clock::now() > deadline || poll(&p, 1, 100) < 0)
      throw std::runtime_error("the server did not start: " + log());
    if (!(p.revents & (POLLIN | POLLHUP))) continue;
    char buf[256];
    ssize_t n = read(stdout_fd_, buf, sizeof buf);
    if (n <= 0) throw std::runtime_error("the server exited at start: " + log());
    line.append(buf, std::size_t(n));
  }
  if (command != "serve") return;  // "bumprad: worker ready ..."
  auto colon = line.find(':', line.find("127.0.0.1"));
  port_ = static_cast<unsigned short>(std::stoi(line.substr(colon + 1)));
}

ServerProcess::~ServerProcess() {
  if (pid_ > 0) kill_hard();
  if (stdout_fd_ >= 0) close(stdout_fd_);
}

int ServerProcess::terminate() {
  kill(pid_, SIGTERM);
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

void ServerProcess::kill_hard() {
  kill(pid_, SIGKILL);
  waitpid(pid_, nullptr, 0);
  pid_ = -1;
}

std::string ServerProcess::log() const {
  std::ifstream in(log_);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string small_scene_json(int max_shots, bool endless) {
  json scene = json::parse(R"({
    "camera": {"position": [0.6, 1.5, 1.9], "look_at": [0, 0.9, 0], "fov_deg": 50,
               "width": 64, "height": 48},
    "materials": {"wall": {"reflectance": 0.6}, "green": {"reflectance": [0.2, 0.6, 0.25]},
                  "light": {"reflectance": 0.5, "emission": 30}},
    "bumps": {"wrinkles": {"type": "wrinkles", "amplitude": 0.01, "scale": 6}},
    "objects": [
      {"type": "box", "material": "wall", "flip_normals": true, "center": [0, 1.5, 0],
       "size": [4, 3, 4]},
      {"type": "quad", "material": "light", "vertices": [[-0.4, 2.99, -0.4], [0.4, 2.99, -0.4],
                                                         [0.4, 2.99, 0.4], [-0.4, 2.99, 0.4]]},
      {"type": "box", "material": "green", "center": [0, 0.8, 0], "size": [0.5, 0.5, 0.5],
       "rotation_deg": [0, 30, 0], "bump": "wrinkles", "mesh": {"element_size": 0.125}}],
    "solver": {"element_size": 0.5, "hemicube_resolution": 48}})");
  scene["solver"]["max_shots"] = endless ? 300'000 : max_shots;
  if (endless) scene["solver"]["unshot_fraction"] = 0;
  return scene.dump();
}

std::string facing_quads_json(int elements, int patch_elements) {
  json mesh = {{"elements", elements}};
  if (patch_elements > 0) mesh["patch_elements"] = patch_elements;
  json scene = json::parse(R"({
    "camera": {"position": [0, 0.5, 3], "look_at": [0, 0.5, 0], "width": 16, "height": 16},
    "materials": {"lamp": {"emission": 10}, "white": {"reflectance": 0.8}},
    "objects": [
      {"type": "quad", "material": "lamp",
       "vertices": [[-0.5, 0.6, -0.5], [0.5, 0.6, -0.5], [0.5, 0.6, 0.5], [-0.5, 0.6, 0.5]]},
      {"type": "quad", "material": "white",
       "vertices": [[-0.5, 0.5, -0.5], [-0.5, 0.5, 0.5], [0.5, 0.5, 0.5], [0.5, 0.5, -0.5]]}],
    "solver": {"max_shots": 2}})");
  for (json& o : scene["objects"]) o["mesh"] = mesh;
  return scene.dump();
}

std::string small_job_json(int max_shots, int preview_every, bool endless) {
  return json{{"scene", json::parse(small_scene_json(max_shots, endless))},
              {"preview_every", preview_every}}
      .dump();
}

std::string wait_for_job(const HttpClient& client, const std::string& id,
                         const std::vector<std::string>& states, double seconds) {
  auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  std::string body;
  while (std::chrono::steady_clock::now() < deadline) {
    HttpResponse r = client.get("/v1/jobs/" + id);
    body = r.body;
    if (r.status == 200) {
      std::string state = json::parse(body)["state"];
      if (std::find(states.begin(), states.end(), state) != states.end()) return body;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  throw std::runtime_error("job " + id + " did not reach the state in time: " + body);
}

}  // namespace bumprad::test
