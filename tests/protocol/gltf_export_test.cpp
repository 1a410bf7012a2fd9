// The lit glTF export read back: a GLB whose JSON chunk describes the solved mesh, whose
// COLOR_0 is each vertex's radiance times the exposure (clamped to glTF's [0, 1]) and whose
// _RADIOSITY is the vertex radiosity itself, with every element's triangles and the scene's
// camera. The Khronos validator's verdict is tests/web/gltf_validate_test.mjs.
#include "protocol/gltf_export.h"

#include <cstring>
#include <numbers>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "solver/radiosity/vertex_radiosity.h"
#include "tests/test_scenes.h"

namespace bumprad {
namespace {

std::uint32_t u32(const std::string& bytes, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, bytes.data() + at, 4);
  return v;
}

TEST(GltfExport, TheModelCarriesEachVertexsLightAndTheMesh) {
  auto lamp = test::rectangle_facing_down(0.6, 0.6, 1.5);
  auto f = test::rectangle_facing_down(3, 3, 0);
  Scene s = test::scene_of({test::quad(lamp, 1, 1, 1), test::quad({f[3], f[2], f[1], f[0]}, 6, 6)});
  Material light;
  light.emission = Rgb(20);
  s.materials.push_back(light);
  s.camera.exposure = 2;
  s.solver.max_shots = 20;
  const Solution solution = solve(s);
  const std::string glb = export_glb(s, solution);

  ASSERT_GE(glb.size(), 28u);
  EXPECT_EQ(u32(glb, 0), 0x46546C67u);  // "glTF"
  EXPECT_EQ(u32(glb, 4), 2u);
  EXPECT_EQ(u32(glb, 8), glb.size());
  const std::uint32_t json_length = u32(glb, 12);
  EXPECT_EQ(u32(glb, 16), 0x4E4F534Au);  // "JSON"
  const auto gltf = nlohmann::json::parse(glb.substr(20, json_length));
  const std::size_t bin = 20 + json_length + 8;
  ASSERT_EQ(u32(glb, bin - 4), 0x004E4942u);  // "BIN"

  const Mesh& mesh = *solution.mesh;
  const auto& primitives = gltf["meshes"][0]["primitives"];
  std::size_t indices = 0, triangles = 0;
  for (const auto& p : primitives) {
    indices += gltf["accessors"][p["indices"].get<std::size_t>()]["count"].get<std::size_t>();
    EXPECT_TRUE(gltf["materials"][p["material"].get<std::size_t>()]["extensions"].contains(
        "KHR_materials_unlit"));
  }
  for (const Element& e : mesh.elements) triangles += e.vertex_count == 4 ? 2 : 1;
  EXPECT_EQ(indices, 3 * triangles);
  EXPECT_EQ(gltf["nodes"][1]["camera"], 0);

  // The vertices in the order the elements first use them (docs/export.md).
  std::vector<std::uint32_t> order;
  std::vector<bool> seen(mesh.vertices.size(), false);
  for (const Element& e : mesh.elements)
    for (int k = 0; k < e.vertex_count; ++k)
      if (!seen[e.v[std::size_t(k)]]) {
        seen[e.v[std::size_t(k)]] = true;
        order.push_back(e.v[std::size_t(k)]);
      }
  // The floats of one VEC3 attribute, vertex by vertex.
  auto floats = [&](const char* name) {
    const auto& a = gltf["accessors"][primitives[0]["attributes"][name].get<std::size_t>()];
    const auto& view = gltf["bufferViews"][a["bufferView"].get<std::size_t>()];
    EXPECT_EQ(a["count"].get<std::size_t>(), order.size()) << name;
    std::vector<float> out(3 * order.size());
    std::memcpy(out.data(), glb.data() + bin + view["byteOffset"].get<std::size_t>(),
                out.size() * sizeof(float));
    return out;
  };
  const std::vector<float> color = floats("COLOR_0"), radiosity = floats("_RADIOSITY"),
                           position = floats("POSITION");
  const std::vector<Rgb> b = vertex_radiosity(mesh, solution.display, solution.open);
  int lit = 0;
  for (std::size_t j = 0; j < order.size(); ++j)
    for (int k = 0; k < 3; ++k) {
      const std::size_t i = order[j];
      const double radiance = b[i][k] * s.camera.exposure / std::numbers::pi;
      ASSERT_NEAR(color[3 * j + k], std::clamp(radiance, 0.0, 1.0), 1e-6) << i;
      ASSERT_NEAR(radiosity[3 * j + k], b[i][k], 1e-6 * std::max(1.0, b[i][k])) << i;
      ASSERT_EQ(position[3 * j + k], float(mesh.vertices[i].position[k]));
      lit += radiance > 0.01 && radiance < 1;
    }
  EXPECT_GT(lit, 30) << "the floor's light shows in COLOR_0 unclamped";
}

}  // namespace
}  // namespace bumprad
