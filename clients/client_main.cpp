// bumprad-client: submits scenes to a bumprad server, follows their refinement steps,
// fetches images and re-textures solved jobs. Talks to the API in protocol/openapi.json.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "clients/event_stream.h"
#include "clients/http_client.h"
#include "clients/progress_bar.h"
#include "common/args.h"
#include "common/atomic_file.h"
#include "common/stopwatch.h"
#include "protocol/job_json.h"

namespace bumprad {
namespace {

constexpr const char* kUsage =
    "usage: bumprad-client [--server http://HOST:PORT] COMMAND ...\n"
    "  submit SCENE.json|builtin:NAME [--bump B.json] [--shots N] [--preview-every K]\n"
    "         [--watch] [--out DIR]   prints the job id; --watch saves each preview to\n"
    "                                 DIR/ID-step-N.png as it arrives, then DIR/ID.png\n"
    "                                 (on a terminal it draws a progress bar)\n"
    "  list                           every job the server keeps, one a line\n"
    "  status ID                      the job as JSON\n"
    "  image ID -o OUT.(png|exr)      the final image\n"
    "  solution ID -o OUT.json        a done job's solution file (for bumprad retexture)\n"
    "  retexture ID --bump B.json -o OUT.(png|exr|jpg)   re-render with new bump functions\n"
    "  cancel ID                      cancel a queued or running job, or delete a finished one\n"
    "The server defaults to $BUMPRAD_SERVER, else http://127.0.0.1:8080.\n";

// An answer that is not the one hoped for: the server's problem, said plainly.
struct ServerError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string read_file(const std::string& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError(std::string("cannot read ") + what + " " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

HttpResponse expect(HttpResponse r, int status) {
  if (r.status != status) throw ServerError(r.problem());
  return r;
}

ImageFormat format_of(const std::string& path) {
  auto f = image_format_for(path);
  if (!f) throw UsageError(path + ": the output must end in .png, .exr or .jpg");
  return *f;
}

struct Args {
  std::vector<std::string> positional;
  std::string bump, output, out_dir = ".";
  std::optional<int> shots, preview_every;
  bool watch = false;
};

Args parse(const std::vector<std::string>& args) {
  Args a;
  const std::vector<std::string_view> views(args.begin(), args.end());
  ArgParser()
      .text({"--bump"}, a.bump)
      .text({"-o", "--output"}, a.output)
      .text({"--out"}, a.out_dir)
      .integer({"--shots"}, a.shots, 1, 1'000'000)
      .integer({"--preview-every"}, a.preview_every, 1, 1'000'000)
      .toggle({"--watch"}, a.watch)
      .positional(a.positional)
      .parse(views);
  return a;
}

void save(const std::filesystem::path& path, const std::string& bytes) {
  write_file_atomically(path, bytes);
}

// Follows the job's events, saving each step's preview; returns the final state's name. On a
// terminal one progress line is redrawn; otherwise (a pipe, a script) a line per step.
std::string watch(const HttpClient& client, const std::string& id, const std::string& dir) {
  std::filesystem::create_directories(dir);
  const bool terminal = ::isatty(STDOUT_FILENO) == 1;
  const auto started = Clock::now();
  EventStreamParser parser;
  std::string final_state;
  auto r = client.stream(job_url(id) + "/events", [&](std::string_view bytes) {
    for (const ServerEvent& e : parser.feed(bytes)) {
      if (e.name == "step") {
        StepEvent step = step_event_from_json(e.data);
        HttpResponse png = client.get(step.preview);
        if (png.status == 200) {  // a step dropped meanwhile is skipped
          auto path =
              std::filesystem::path(dir) / (id + "-step-" + std::to_string(step.step) + ".png");
          save(path, png.body);
          if (terminal)
            std::printf("\r%s", progress_line(step.shots, step.max_shots, step.unshot_fraction,
                                              step.step, seconds_since(started))
                                    .c_str());
          else
            std::printf("step %d: %d/%d shots, unshot %.2f%% -> %s\n", step.step, step.shots,
                        step.max_shots, 100 * step.unshot_fraction, path.c_str());
          std::fflush(stdout);
        }
      } else if (e.name != "state") {
        if (terminal) std::printf("\nsteps saved in %s\n", dir.c_str());
        final_state = e.name;
        JobRecord job = job_from_json(e.data);
        if (!job.error.empty()) std::fprintf(stderr, "job %s: %s\n", id.c_str(), job.error.c_str());
        for (const std::string& w : job.warnings)
          std::fprintf(stderr, "job %s: warning: %s\n", id.c_str(), w.c_str());
        return false;
      }
    }
    return true;
  });
  if (r.status != 200) throw ServerError(r.problem());
  if (final_state.empty()) throw ServerError("the event stream ended before the job did");
  return final_state;
}

int run(const std::string& server, const std::vector<std::string>& argv) {
  if (argv.empty()) throw UsageError("no command given");
  auto [host, port] = parse_server_url(server);
  HttpClient client(host, port);
  const std::string& command = argv[0];
  Args a = parse({argv.begin() + 1, argv.end()});
  auto id_arg = [&]() -> std::string {
    if (a.positional.size() != 1) throw UsageError(command + " takes one job id");
    return a.positional[0];
  };
  if (command == "submit") {
    if (a.positional.size() != 1) throw UsageError("submit takes one scene");
    JobSubmission s;
    if (a.positional[0].starts_with("builtin:"))
      s.builtin = a.positional[0].substr(8);
    else
      s.scene_json = read_file(a.positional[0], "the scene");
    if (!a.bump.empty()) s.bumps_json = read_file(a.bump, "the bump file");
    s.max_shots = a.shots;
    s.preview_every = a.preview_every;
    HttpResponse r = expect(client.request("POST", "/v1/jobs", job_request_json(s)), 202);
    std::string id = job_from_json(r.body).id;
    std::printf("%s\n", id.c_str());
    std::fflush(stdout);
    if (!a.watch) return 0;
    std::string state = watch(client, id, a.out_dir);
    if (state != "done") {
      std::fprintf(stderr, "job %s ended %s\n", id.c_str(), state.c_str());
      return 1;
    }
    auto path = std::filesystem::path(a.out_dir) / (id + ".png");
    save(path, expect(client.get(job_url(id) + "/image"), 200).body);
    std::printf("done -> %s\n", path.c_str());
    return 0;
  }
  if (command == "list") {
    if (!a.positional.empty()) throw UsageError("list takes no arguments");
    const auto jobs = jobs_from_json(expect(client.get("/v1/jobs"), 200).body);
    std::printf("%-16s  %-11s  %7s  %7s  %s\n", "ID", "STATE", "SHOTS", "UNSHOT", "SCENE");
    for (const JobRecord& j : jobs)
      std::printf("%-16s  %-11s  %7d  %6.2f%%  %s\n", j.id.c_str(),
                  std::string(to_string(j.state)).c_str(), j.shots, 100 * j.unshot_fraction,
                  j.scene_name.c_str());
    return 0;
  }
  if (command == "solution") {
    std::string id = id_arg();
    if (a.output.empty()) throw UsageError("solution needs -o OUT.json");
    save(a.output, expect(client.get(job_url(id) + "/solution"), 200).body);
    std::printf("wrote %s\n", a.output.c_str());
    return 0;
  }
  if (command == "status") {
    std::printf("%s\n", expect(client.get(job_url(id_arg())), 200).body.c_str());
    return 0;
  }
  if (command == "image") {
    std::string id = id_arg();
    if (a.output.empty()) throw UsageError("image needs -o OUT.png or OUT.exr");
    const ImageFormat f = format_of(a.output);
    if (f == ImageFormat::Jpeg)
      throw UsageError("the final image is kept as PNG and EXR: use -o OUT.png or OUT.exr");
    const std::string format(format_name(f));
    save(a.output, expect(client.get(job_url(id) + "/image?format=" + format), 200).body);
    std::printf("wrote %s\n", a.output.c_str());
    return 0;
  }
  if (command == "retexture") {
    std::string id = id_arg();
    if (a.output.empty()) throw UsageError("retexture needs -o OUT.png, OUT.exr or OUT.jpg");
    std::string bumps = a.bump.empty() ? "" : read_file(a.bump, "the bump file");
    std::string body = retexture_request_json(bumps, format_of(a.output));
    save(a.output, expect(client.request("POST", job_url(id) + "/retexture", body), 200).body);
    std::printf("wrote %s\n", a.output.c_str());
    return 0;
  }
  if (command == "cancel") {
    HttpResponse r = client.request("DELETE", job_url(id_arg()));
    if (r.status == 204) {
      std::printf("deleted\n");
      return 0;
    }
    std::printf("%s\n", job_from_json(expect(r, 202).body).state == JobState::Cancelled
                            ? "cancelled"
                            : "cancelling (stops within one shot)");
    return 0;
  }
  throw UsageError("unknown command \"" + command + "\"");
}

}  // namespace
}  // namespace bumprad

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  const char* env = std::getenv("BUMPRAD_SERVER");
  std::string server = env && *env ? env : "http://127.0.0.1:8080";
  if (args.size() >= 2 && args[0] == "--server") {
    server = args[1];
    args.erase(args.begin(), args.begin() + 2);
  }
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    std::cout << bumprad::kUsage;
    return 0;
  }
  try {
    return bumprad::run(server, args);
  } catch (const bumprad::UsageError& e) {
    std::cerr << "bumprad-client: " << e.what() << "\n" << bumprad::kUsage;
    return 2;
  } catch (const bumprad::MalformedJson& e) {
    std::cerr << "bumprad-client: " << e.reason() << "\n";
    return 1;
  } catch (const std::invalid_argument& e) {
    std::cerr << "bumprad-client: --server: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "bumprad-client: " << e.what() << "\n";
    return 1;
  }
}
