// Import benchmark: how long a model takes to read, mesh, solve and render at bumprad's
// defaults, per file.
//   build/bin/bumprad-bench-import [MODEL...] [--width W] [--images DIR]
// Without MODELs, Debian's assimp-testmodels set below. A model that emits no light gets a
// lamp: a square a third of its extent across, a third of its extent above the camera,
// facing the point the camera looks at, so the solve has light to shoot and the camera sees
// it land; the camera is the model's own, or framed on the model alone.
// With --images, each render is written to DIR/<model>.png. The numbers go in the README with
// the machine.
#include <algorithm>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "common/args.h"
#include "common/stopwatch.h"
#include "protocol/scene_json.h"
#include "protocol/scene_source.h"
#include "solver/scene/mesh.h"
#include "solver/solution.h"
#include "solver/util/image.h"

namespace {

using json = nlohmann::json;

const std::vector<std::string> kDefaultModels = {
    "/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb",
    "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
    "/usr/share/assimp/models/OBJ/spider.obj",
    "/usr/share/assimp/models/OBJ/WusonOBJ.obj",
};

json vec(const bumprad::Vec3& v) {
  return {v.x, v.y, v.z};
}

}  // namespace

int main(int argc, char** argv) {
  using namespace bumprad;
  std::vector<std::string> models;
  int width = 0;
  std::string images;
  ArgParser()
      .integer({"--width"}, width, 1, Limits::kMaxImageSide)
      .text({"--images"}, images)
      .positional(models, 1000)
      .parse_or_exit(argc, argv,
                     "usage: bumprad-bench-import [MODEL...] [--width W] [--images DIR]\n");
  if (models.empty()) models = kDefaultModels;
  std::printf("%-22s %9s %9s %8s %9s %7s %7s %9s %9s\n", "model", "triangles", "elements",
              "patches", "import s", "shots", "solve s", "render s", "image");
  for (const std::string& file : models) {
    try {
      auto t0 = Clock::now();
      std::string text;
      Scene bare = load_scene(file, &text);
      const double import_s = seconds_since(t0);
      json doc = json::parse(text);
      doc["camera"] = {
          {"position", vec(bare.camera.position)},
          {"look_at", vec(bare.camera.look_at)},
          {"up", vec(bare.camera.up)},
          {"fov_deg", bare.camera.fov_y_deg},
          {"width", width > 0 ? width : bare.camera.width},
          {"height", width > 0 ? std::max(1, width * bare.camera.height / bare.camera.width)
                               : bare.camera.height}};
      std::size_t triangles = 0;
      bool emits = false;
      Vec3 lo(1e300), hi(-1e300);
      for (const Object& o : bare.objects)
        if (const auto* m = std::get_if<TriangleMeshShape>(&o.shape)) {
          triangles += m->triangles.size();
          for (const Vec3& p : m->positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
        }
      for (const Material& m : bare.materials) emits = emits || m.emission != Rgb(0);
      if (!emits) {
        const Vec3 e = hi - lo;
        const double r = std::max({e.x, e.y, e.z}) / 6;
        const Camera& c = bare.camera;
        const Vec3 at = c.position + glm::normalize(c.up) * (2 * r);
        const Vec3 facing = glm::normalize(c.look_at - at);
        const Vec3 side = glm::normalize(glm::cross(facing, c.up)), up = glm::cross(side, facing);
        // About unit irradiance where the camera looks: E A / (pi d^2) = 1.
        const double d = glm::length(c.look_at - at);
        doc["materials"]["bench lamp"] = {{"reflectance", 0},
                                          {"emission", std::numbers::pi * d * d / (4 * r * r)}};
        // Counter-clockwise seen from where it faces.
        doc["objects"].push_back({{"type", "quad"},
                                  {"material", "bench lamp"},
                                  {"vertices",
                                   {vec(at - r * side - r * up), vec(at - r * side + r * up),
                                    vec(at + r * side + r * up), vec(at + r * side - r * up)}}});
      }
      const Scene scene = parse_scene(doc);
      t0 = Clock::now();
      const Solution solution = solve(scene);
      const double solve_s = seconds_since(t0);
      t0 = Clock::now();
      const Image image = render(scene, solution);
      const double render_s = seconds_since(t0);
      const std::string name = file.substr(file.find_last_of('/') + 1);
      if (!images.empty()) write_image(images + "/" + name + ".png", image, scene.camera.exposure);
      std::printf("%-22s %9zu %9zu %8zu %9.3f %7d %7.2f %9.2f %4dx%-4d%s\n", name.c_str(),
                  triangles, solution.mesh->elements.size(), solution.mesh->patches.size(),
                  import_s, solution.stats.shots, solve_s, render_s, scene.camera.width,
                  scene.camera.height, emits ? "" : "  (lamp added)");
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", file.c_str(), e.what());
      return 1;
    }
  }
  return 0;
}
