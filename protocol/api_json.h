// The HTTP API's requests that carry scenes (protocol/openapi.json): job and re-texture
// requests to validated scenes, cost answers, the built-in scenes' list. Every rejection is
// a SceneError naming the request's field. Job records and events are in job_json.h.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "protocol/job_json.h"
#include "protocol/scene_json.h"
#include "solver/scene/scene.h"

namespace bumprad {

struct JobRequest {
  Scene scene;
  std::string scene_json;     // the scene with the request's overrides merged in: what is solved
  std::string scene_name;     // for JobRecord::scene_name
  bool inline_scene = false;  // sent as "scene" (its fields under /scene), not "builtin"
  std::vector<std::string> warnings;  // what its models' importer dropped or assumed
};

// POST /v1/jobs: {"scene": {..}} or {"builtin": NAME}, optional "bumps" (replacing the
// scene's by name), "solver" (settings) and "preview_every". Without a preview_every here or
// in the scene, a job previews about 20 steps. Throws MalformedJson or SceneError whose
// pointer is into the request ("/scene/objects/0/size", "/bumps/wall/amplitude").
JobRequest parse_job_request(std::string_view body, const ImageFiles& files);

struct RetextureRequest {
  Scene scene;  // the solved scene with the new bump functions and camera
  ImageFormat format = ImageFormat::Png;
};

// POST /v1/jobs/{id}/retexture: optional "bumps" (by name), "camera" (the keys of a camera
// block to change), "format" ("png", "exr" or "jpeg") and "quality" ("final", or "draft":
// draft_camera, for interactive editing) applied to the solved scene. Geometry cannot
// change, so the stored perturbed map stays valid.
RetextureRequest parse_retexture_request(std::string_view body, const Scene& solved,
                                         const ImageFiles& files);

// POST /v1/validate's answer: the request would be accepted, at this estimated cost.
std::string validation_json(double solve_s, double render_s, double limit_s);

// GET /v1/scenes: the built-in scenes, by name and description.
std::string builtin_scenes_json();

}  // namespace bumprad
