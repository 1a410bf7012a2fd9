#include "protocol/api_json.h"

#include <array>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "protocol/builtin_scenes.h"
#include "protocol/json_node.h"
#include "solver/scene/camera.h"

namespace bumprad {
namespace {

using json = nlohmann::json;

// Jobs that set no preview_every get about this many refinement steps.
constexpr int kDefaultSteps = 20;

// A SceneError from a part of the request, relocated to where that part sits in it.
[[noreturn]] void rethrow_under(const SceneError& e, const std::string& prefix) {
  throw SceneError(prefix + e.pointer(), e.reason());
}

void require_object(const json& value, const std::string& pointer, const char* what) {
  if (!value.is_object()) throw SceneError(pointer, std::string("must be ") + what);
}

// How the job list names a scene sent inline: by its description, cut at a word near 60
// characters, or "inline scene" when it has none.
std::string inline_scene_name(const json& scene) {
  constexpr std::size_t kLength = 60;
  const auto d = scene.find("description");
  if (d == scene.end() || !d->is_string() || d->get_ref<const std::string&>().empty())
    return "inline scene";
  std::string name = d->get<std::string>();
  if (name.size() <= kLength) return name;
  std::size_t cut = name.rfind(' ', kLength);
  if (cut == std::string::npos || cut < kLength / 2) cut = kLength;
  while (cut > 0 && (static_cast<unsigned char>(name[cut]) & 0xC0) == 0x80) --cut;  // UTF-8
  return name.substr(0, cut) + "…";
}

}  // namespace

JobRequest parse_job_request(std::string_view body, const ImageFiles& files) {
  json request = parse_json(body);
  require_object(request, "", "a JSON object");
  Node(request, "").allow_only({"scene", "builtin", "bumps", "solver", "preview_every"}, "job");

  JobRequest out;
  json scene;
  std::string prefix;
  if (request.contains("scene") == request.contains("builtin"))
    throw SceneError("/scene", "give either \"scene\" (inline JSON) or \"builtin\" (a name)");
  if (request.contains("builtin")) {
    const std::string name = Node(request["builtin"], "/builtin").string();
    auto text = find_builtin_scene(name);
    if (!text) {
      std::string names;
      for (const auto& s : builtin_scenes())
        names += (names.empty() ? "" : ", ") + std::string(s.name);
      throw SceneError("/builtin",
                       "unknown built-in scene \"" + name + "\" (there are: " + names + ")");
    }
    scene = json::parse(*text);
    out.scene_name = "builtin:" + name;
  } else {
    scene = request["scene"];
    require_object(scene, "/scene", "a scene object");
    out.scene_name = inline_scene_name(scene);
    out.inline_scene = true;
    prefix = "/scene";
  }

  // Each override is checked where the request has it, then merged into the scene, so the
  // stored scene JSON alone reproduces the job.
  try {
    out.scene = parse_scene(scene, files, &out.warnings);
    for (std::string& w : out.warnings) w = prefix + w;  // where the request has the field
  } catch (const SceneError& e) {
    rethrow_under(e, prefix);
  }
  if (request.contains("bumps")) {
    const json& bumps = request["bumps"];
    require_object(bumps, "/bumps", "an object of bump functions by name");
    apply_bump_overrides(bumps, out.scene, "/bumps", files);
    for (auto it = bumps.begin(); it != bumps.end(); ++it) scene["bumps"][it.key()] = it.value();
  }
  json settings = request.value("solver", json::object());
  require_object(settings, "/solver", "an object of solver settings");
  apply_solver_settings(settings, out.scene.solver, "/solver");
  if (request.contains("preview_every")) {
    json every = {{"preview_every", request["preview_every"]}};
    apply_solver_settings(every, out.scene.solver, "");
    settings["preview_every"] = request["preview_every"];
  }
  bool scene_sets_preview = scene.contains("solver") && scene["solver"].contains("preview_every");
  if (!settings.contains("preview_every") && !scene_sets_preview) {
    settings["preview_every"] =
        std::max(1, int(std::ceil(double(out.scene.solver.max_shots) / kDefaultSteps)));
    out.scene.solver.preview_every = settings["preview_every"].get<int>();
  }
  if (!settings.empty()) {
    if (!scene.contains("solver")) scene["solver"] = json::object();
    scene["solver"].update(settings);
  }
  out.scene_json = scene.dump(2);
  return out;
}

RetextureRequest parse_retexture_request(std::string_view body, const Scene& solved,
                                         const ImageFiles& files) {
  json request = body.empty() ? json::object() : parse_json(body);
  require_object(request, "", "a JSON object");
  Node(request, "").allow_only({"bumps", "camera", "format", "quality"}, "re-texture request");
  RetextureRequest out{solved, ImageFormat::Png};
  if (request.contains("bumps")) {
    require_object(request["bumps"], "/bumps", "an object of bump functions by name");
    apply_bump_overrides(request["bumps"], out.scene, "/bumps", files);
  }
  if (request.contains("camera"))
    out.scene.camera = parse_camera_changes(request["camera"], solved.camera, "/camera");
  if (request.contains("format"))
    out.format =
        Node(request["format"], "/format")
            .one_of<ImageFormat>(
                {{"png", ImageFormat::Png}, {"exr", ImageFormat::Exr}, {"jpeg", ImageFormat::Jpeg}},
                "image format");
  if (request.contains("quality") &&
      Node(request["quality"], "/quality")
          .one_of<bool>({{"final", false}, {"draft", true}}, "quality"))
    out.scene.camera = draft_camera(out.scene.camera);
  return out;
}

std::string validation_json(double solve_s, double render_s, double limit_s) {
  return json{{"valid", true},
              {"estimate", {{"solve_s", solve_s}, {"render_s", render_s}, {"limit_s", limit_s}}}}
      .dump();
}

std::string builtin_scenes_json() {
  json list = json::array();
  for (const auto& s : builtin_scenes())
    list.push_back(
        {{"name", s.name}, {"description", json::parse(s.json).value("description", "")}});
  return json{{"scenes", list}}.dump();
}

}  // namespace bumprad
