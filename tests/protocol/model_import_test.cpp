// Models through Assimp: the Cornell box written as OBJ + MTL renders like the built-in
// scene; node transforms place meshes (a mirroring one keeps them facing out); real files
// from Debian's assimp-testmodels keep their texture coordinates, materials and cameras;
// bad files are refused naming the file and the mesh.
#include "protocol/model_import.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "protocol/base64.h"
#include "protocol/scene_json.h"
#include "protocol/scene_source.h"
#include "solver/render/error_estimate.h"
#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"
#include "solver/scene/texture.h"
#include "solver/solution.h"
#include "solver/util/image.h"
#include "tests/test_files.h"

namespace bumprad {
namespace {

using test::kTestModels;

// The built-in Cornell box's quads as an OBJ with its materials in an MTL (Kd, and Ke the
// emitted radiance: emission / pi).
std::filesystem::path cornell_as_obj(const std::filesystem::path& dir) {
  const Scene cornell = load_scene("builtin:cornell");
  std::ofstream mtl(dir / "cornell.mtl");
  for (const Material& m : cornell.materials) {
    mtl << "newmtl " << m.name << "\nKd " << m.reflectance.r << " " << m.reflectance.g << " "
        << m.reflectance.b << "\n";
    const Rgb radiance = m.emission / std::numbers::pi;
    mtl << "Ke " << radiance.r << " " << radiance.g << " " << radiance.b << "\n";
  }
  std::ofstream obj(dir / "cornell.obj");
  obj.precision(17);
  obj << "mtllib cornell.mtl\n";
  int next = 1;
  for (const Object& o : cornell.objects) {
    const auto& q = std::get<QuadShape>(o.shape);
    std::string name = o.name;
    std::replace(name.begin(), name.end(), ' ', '_');  // OBJ names end at a space
    obj << "o " << name << "\nusemtl " << cornell.materials[std::size_t(o.material)].name << "\n";
    for (const Vec3& p : q.corners) obj << "v " << p.x << " " << p.y << " " << p.z << "\n";
    obj << "f " << next << " " << next + 1 << " " << next + 2 << " " << next + 3 << "\n";
    next += 4;
  }
  return dir / "cornell.obj";
}

double area_of(const Mesh& mesh, const std::vector<Material>& materials, const std::string& name) {
  double a = 0;
  for (const Element& e : mesh.elements)
    if (materials[std::size_t(e.material)].name == name) a += e.area;
  return a;
}

// Imported, the box has the built-in's surfaces (to float precision, and the triangulation of
// its slightly bent walls), materials and emission, and
// rendered with the same camera and solver settings its image is within 2 % of the
// built-in's (relative RMS over the pixels that show no emitter). Measured 1.67 %, mostly the
// shadow rays' noise in the penumbrae, drawn differently over different meshes
// (docs/import.md, "Measured"), not the triangles themselves.
TEST(ModelImport, TheCornellBoxAsObjRendersLikeTheBuiltIn) {
  const auto dir = test::fresh_temp_dir("import-cornell");
  Scene builtin = load_scene("builtin:cornell");
  Scene imported = load_scene(cornell_as_obj(dir).string());
  ASSERT_EQ(imported.objects.size(), builtin.objects.size());
  // The file has no camera: the box's faces turn in, so it is framed as a room, from outside
  // its open side (z < 0, as its own camera stands), looking at its centre.
  EXPECT_LT(imported.camera.position.z, -500);
  EXPECT_NEAR(imported.camera.look_at.z, 559.2 / 2, 1);
  EXPECT_NEAR(imported.camera.position.x, imported.camera.look_at.x, 1e-9);
  for (Scene* s : {&builtin, &imported}) {
    s->camera = builtin.camera;
    s->camera.width = s->camera.height = 96;
    s->solver = builtin.solver;
  }
  const Mesh a = build_mesh(builtin), b = build_mesh(imported);
  for (const char* m : {"white", "red", "green", "light"})
    EXPECT_NEAR(area_of(b, imported.materials, m), area_of(a, builtin.materials, m),
                1e-5 * area_of(a, builtin.materials, m))
        << m;
  for (const Material& m : imported.materials)
    for (const Material& original : builtin.materials)
      if (m.name == original.name) {
        EXPECT_NEAR(glm::length(m.emission - original.emission), 0, 1e-3) << m.name;
        EXPECT_NEAR(glm::length(m.reflectance - original.reflectance), 0, 1e-6) << m.name;
      }

  const Image reference = render(builtin, solve(builtin));
  const Solution solution = solve(imported);
  const Image image = render(imported, solution);
  const std::vector<bool> emitter = emitter_pixels(imported, *solution.mesh, *solution.rays);
  double diff = 0, norm = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      if (emitter[std::size_t(y * image.width + x)]) continue;
      const Rgb d = image.at(x, y) - reference.at(x, y);
      diff += glm::dot(d, d);
      norm += glm::dot(reference.at(x, y), reference.at(x, y));
    }
  const double error = std::sqrt(diff / norm);
  std::printf("imported cornell against the built-in: %.4f\n", error);
  EXPECT_LT(error, 0.02);
}

// The unit quad in z = 0 (facing +z, uvs over [0,1]^2) as glTF buffer data, written to
// dir/NAME.bin: its primitive's "attributes" and "indices", and the file's "buffers",
// "bufferViews" and "accessors" members. With `tangents`, also normals (+z) and a TANGENT a
// quarter turn from what the uvs give (+y, w = +1).
struct QuadBuffers {
  nlohmann::json attributes;
  std::size_t indices = 0;
  std::string members;  // to splice into the file's top-level object

  // The mesh primitive, of material 0.
  std::string primitive() const {
    return nlohmann::json{{"attributes", attributes}, {"indices", indices}, {"material", 0}}.dump();
  }
};
QuadBuffers unit_quad_buffers(const std::filesystem::path& dir, const std::string& name,
                              bool tangents) {
  struct Block {
    std::string attribute, type;
    std::vector<float> values;
  };
  std::vector<Block> blocks{{"POSITION", "VEC3", {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}},
                            {"TEXCOORD_0", "VEC2", {0, 0, 1, 0, 1, 1, 0, 1}}};
  if (tangents) {
    blocks.push_back({"NORMAL", "VEC3", {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}});
    blocks.push_back({"TANGENT", "VEC4", {0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1}});
  }
  QuadBuffers out;
  nlohmann::json views = nlohmann::json::array(), accessors = nlohmann::json::array();
  std::string bytes;
  for (const Block& b : blocks) {
    out.attributes[b.attribute] = accessors.size();
    views.push_back({{"buffer", 0},
                     {"byteOffset", bytes.size()},
                     {"byteLength", b.values.size() * sizeof(float)}});
    nlohmann::json accessor = {
        {"bufferView", views.size() - 1}, {"componentType", 5126}, {"count", 4}, {"type", b.type}};
    if (b.attribute == "POSITION") accessor.update({{"min", {0, 0, 0}}, {"max", {1, 1, 0}}});
    accessors.push_back(accessor);
    bytes.append(reinterpret_cast<const char*>(b.values.data()), b.values.size() * sizeof(float));
  }
  const std::uint16_t indices[] = {0, 1, 2, 0, 2, 3};
  out.indices = accessors.size();
  views.push_back({{"buffer", 0}, {"byteOffset", bytes.size()}, {"byteLength", sizeof indices}});
  accessors.push_back({{"bufferView", views.size() - 1},
                       {"componentType", 5123},
                       {"count", 6},
                       {"type", "SCALAR"}});
  bytes.append(reinterpret_cast<const char*>(indices), sizeof indices);
  std::ofstream(dir / (name + ".bin"), std::ios::binary) << bytes;
  const std::string members = nlohmann::json{
      {"buffers", {{{"uri", name + ".bin"}, {"byteLength", bytes.size()}}}},
      {"bufferViews", views},
      {"accessors", accessors}}.dump();
  out.members = members.substr(1, members.size() - 2);
  return out;
}

// Writes a glTF whose one quad (z = 0, facing +z, uvs over [0,1]^2) sits under a node that
// moves it by (5, 0, 0) and mirrors x: the quad lands at x in [4, 5] and still faces +z.
// `material` replaces its one material; `extra` adds top-level keys (textures, images);
// `holder` adds keys to the moving node (a light's extension).
std::filesystem::path mirrored_quad_gltf(const std::filesystem::path& dir,
                                         const std::string& material =
                                             R"({"name": "glow", "pbrMetallicRoughness":
                                                 {"baseColorFactor": [0.5, 0.25, 1, 1],
                                                  "metallicFactor": 0},
                                                 "emissiveFactor": [1, 0.5, 0.25]})",
                                         const std::string& extra = "",
                                         const std::string& holder = "") {
  const QuadBuffers quad = unit_quad_buffers(dir, "quad", false);
  std::ofstream(dir / "quad.gltf") << R"({
  "asset": {"version": "2.0"},
  "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"name": "holder", "translation": [5, 0, 0], "children": [1])" +
                                          holder + R"(},
            {"name": "mirror", "scale": [-1, 1, 1], "mesh": 0}],
  "meshes": [{"name": "quad", "primitives": [)" +
                                          quad.primitive() + R"(]}],
  "materials": [)" + material + R"(],)" + extra +
                                          quad.members + "}";
  return dir / "quad.gltf";
}

TEST(ModelImport, NodeTransformsPlaceMeshesAndAMirrorKeepsThemFacingOut) {
  const auto dir = test::fresh_temp_dir("import-gltf");
  const auto file = mirrored_quad_gltf(dir);
  const ImportedModel model = import_model(file);
  ASSERT_EQ(model.objects.size(), 1u);
  EXPECT_EQ(model.objects[0].name, "mirror/quad");
  const auto& shape = std::get<TriangleMeshShape>(model.objects[0].shape);
  Vec3 lo = shape.positions[0], hi = lo;
  for (const Vec3& p : shape.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  EXPECT_EQ(lo, Vec3(4, 0, 0));
  EXPECT_EQ(hi, Vec3(5, 1, 0));
  ASSERT_EQ(shape.uvs.size(), shape.positions.size());
  const Material& m = model.materials[std::size_t(model.objects[0].material)];
  EXPECT_EQ(m.name, "glow");
  EXPECT_NEAR(glm::length(m.reflectance - Rgb(0.5, 0.25, 0.99)), 0, 1e-6);  // 1 read as 0.99
  EXPECT_NEAR(glm::length(m.emission - std::numbers::pi * Rgb(1, 0.5, 0.25)), 0, 1e-6);
  // The file alone is a scene: its one model, named for the file.
  const Scene scene = load_scene(file.string());
  EXPECT_EQ(scene.objects[0].name, "quad/mirror/quad");
  const Mesh mesh = build_mesh(scene);
  ASSERT_FALSE(mesh.elements.empty());
  for (const Element& e : mesh.elements) EXPECT_NEAR(e.normal.z, 1, 1e-9);
  // The uvs follow the (mirrored) quad: u runs along -x.
  for (const Vertex& v : mesh.vertices) {
    EXPECT_NEAR(v.uv.x, 5 - v.position.x, 1e-6);
    EXPECT_NEAR(v.uv.y, v.position.y, 1e-6);
  }
  // No camera in the file: one framed on the model, looking at its centre.
  EXPECT_EQ(scene.camera.look_at, Vec3(4.5, 0.5, 0));
  EXPECT_GT(scene.camera.position.z, 0);
}

// KHR_materials_emissive_strength multiplies the emissive factor (Blender writes it for any
// strength above 1; Assimp 5.2 does not read it, so it comes from the file's JSON).
TEST(ModelImport, EmissiveStrengthMultipliesTheEmission) {
  const auto dir = test::fresh_temp_dir("import-emissive-strength");
  const ImportedModel model =
      import_model(mirrored_quad_gltf(dir, R"({"name": "lamp", "emissiveFactor": [1, 0.5, 0.25],
               "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 12}}})"));
  const Material& m = model.materials[std::size_t(model.objects[0].material)];
  EXPECT_NEAR(glm::length(m.emission - 12 * std::numbers::pi * Rgb(1, 0.5, 0.25)), 0, 1e-5);
}

// The unit quad with normals and a TANGENT (unit_quad_buffers), under a node that mirrors x.
std::filesystem::path tangent_quad_gltf(const std::filesystem::path& dir) {
  const QuadBuffers quad = unit_quad_buffers(dir, "tangents", true);
  std::ofstream(dir / "tangents.gltf") << R"({
  "asset": {"version": "2.0"},
  "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"name": "mirror", "scale": [-1, 1, 1], "mesh": 0}],
  "meshes": [{"name": "quad", "primitives": [)" +
                                              quad.primitive() + R"(]}],
  "materials": [{"name": "plain", "pbrMetallicRoughness": {"metallicFactor": 0}}],)" +
                                              quad.members + "}";
  return dir / "tangents.gltf";
}

// A file's TANGENT sets the normal-map frame: carried through the node's mirror (which
// keeps +y and turns the handedness: w (n x t) was -x up the texture, and the mirror makes
// it +x), and through a placement's mirror back again.
TEST(ModelImport, TangentsFromTheFileTurnWithTheirTransforms) {
  const auto dir = test::fresh_temp_dir("import-tangents");
  ImportedModel model = import_model(tangent_quad_gltf(dir));
  ASSERT_EQ(model.objects.size(), 1u);
  const auto& shape = std::get<TriangleMeshShape>(model.objects[0].shape);
  ASSERT_EQ(shape.tangents.size(), shape.positions.size());
  for (const glm::dvec4& t : shape.tangents)
    EXPECT_NEAR(glm::length(t - glm::dvec4(0, 1, 0, -1)), 0, 1e-6);
  // dp/du along the tangent, dp/dv (down the texture) against w (n x t); both unit long, as
  // the unit quad's (u, v) make them.
  Scene scene = load_scene(tangent_quad_gltf(dir).string());
  for (const Vertex& v : build_mesh(scene).vertices) {
    EXPECT_NEAR(glm::length(v.dpdu - Vec3(0, 1, 0)), 0, 1e-6);
    EXPECT_NEAR(glm::length(v.dpdv - Vec3(-1, 0, 0)), 0, 1e-6);
  }
  transform_model(model, glm::scale(glm::dmat4(1), Vec3(-1, 1, 1)));
  for (const glm::dvec4& t : std::get<TriangleMeshShape>(model.objects[0].shape).tangents)
    EXPECT_NEAR(glm::length(t - glm::dvec4(0, 1, 0, 1)), 0, 1e-6);
}

// Cut-outs and see-through materials are drawn opaque, and the import says so.
TEST(ModelImport, AlphaModesOtherThanOpaqueAreNamedInAWarning) {
  for (const std::string mode : {"MASK", "BLEND", "OPAQUE"}) {
    const auto dir = test::fresh_temp_dir("import-alpha");
    const ImportedModel model = import_model(
        mirrored_quad_gltf(dir, R"({"name": "leaf", "alphaMode": ")" + mode + R"("})"));
    const bool warned =
        std::any_of(model.warnings.begin(), model.warnings.end(), [&](const std::string& w) {
          return w.find("material \"leaf\": its alphaMode " + mode + " is read as OPAQUE") !=
                 std::string::npos;
        });
    EXPECT_EQ(warned, mode != "OPAQUE") << mode;
  }
}

// A glTF camera stands at its node's origin, looks along the node's -z, and keeps the file's
// vertical field of view and aspect ratio (Assimp alone put it at twice the node's
// translation with twice the angle: a room rendered small and off centre).
TEST(ModelImport, AGltfCameraStandsWhereItsNodePutsIt) {
  const auto dir = test::fresh_temp_dir("import-camera");
  const auto file =
      mirrored_quad_gltf(dir, R"({"name": "plain", "pbrMetallicRoughness": {"metallicFactor": 0}})",
                         R"("cameras": [{"type": "perspective",
                      "perspective": {"yfov": 0.5, "aspectRatio": 2, "znear": 0.1}}],)",
                         R"(, "camera": 0, "rotation": [0, 0.70710678, 0, 0.70710678])");
  const ImportedModel model = import_model(file);
  ASSERT_TRUE(model.camera);
  const Camera& c = *model.camera;
  EXPECT_NEAR(glm::length(c.position - Vec3(5, 0, 0)), 0, 1e-6);
  // A quarter turn about +y takes -z to -x.
  EXPECT_NEAR(glm::length(glm::normalize(c.look_at - c.position) - Vec3(-1, 0, 0)), 0, 1e-6);
  EXPECT_NEAR(glm::length(c.up - Vec3(0, 1, 0)), 0, 1e-6);
  EXPECT_NEAR(c.fov_y_deg, 0.5 * 180 / std::numbers::pi, 1e-4);
  EXPECT_EQ(c.width, 512);
  EXPECT_EQ(c.height, 256);
  EXPECT_NEAR(glm::length(load_scene(file.string()).camera.position - Vec3(5, 0, 0)), 0, 1e-6);
}

// glTF's doubleSided: an open sheet gets its back as a second sheet facing the other way; a
// closed mesh (the real test box, doubleSided too) is left alone, its back never seen.
TEST(ModelImport, DoubleSidedSheetsGetABackAndClosedMeshesDoNot) {
  const auto dir = test::fresh_temp_dir("import-double-sided");
  const ImportedModel sheet = import_model(mirrored_quad_gltf(
      dir,
      R"({"name": "leaf", "doubleSided": true, "pbrMetallicRoughness": {"metallicFactor": 0}})"));
  const auto& m = std::get<TriangleMeshShape>(sheet.objects[0].shape);
  ASSERT_EQ(m.triangles.size(), 4u);
  Scene scene;
  scene.materials = sheet.materials;
  scene.objects = sheet.objects;
  int front = 0, back = 0;
  for (const Element& e : build_mesh(scene).elements) {
    front += e.normal.z > 0.999;
    back += e.normal.z < -0.999;
  }
  EXPECT_GT(front, 0);
  EXPECT_EQ(back, front);
  const ImportedModel one_sided = import_model(mirrored_quad_gltf(dir));
  EXPECT_EQ(std::get<TriangleMeshShape>(one_sided.objects[0].shape).triangles.size(), 2u);
  const ImportedModel box = import_model(kTestModels / "glTF2/BoxTexcoords-glTF/boxTexcoords.gltf");
  std::size_t triangles = 0;
  for (const Object& o : box.objects)
    triangles += std::get<TriangleMeshShape>(o.shape).triangles.size();
  EXPECT_EQ(triangles, 12u);
}

// KHR_lights_punctual: a point light on the node that moves the quad (so at (5, 0, 0)),
// 683 cd -> 1 W/sr; a spot's cone angles.
TEST(ModelImport, PunctualLightsArePlacedAndConverted) {
  const auto dir = test::fresh_temp_dir("import-lights");
  const ImportedModel model = import_model(
      mirrored_quad_gltf(dir, R"({"name": "plain", "pbrMetallicRoughness": {"metallicFactor": 0}})",
                         R"(
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [
    {"name": "bulb", "type": "point", "color": [1, 0.5, 0.25], "intensity": 683}]}},)",
                         R"(, "extensions": {"KHR_lights_punctual": {"light": 0}})"));
  ASSERT_EQ(model.lights.size(), 1u);
  const PunctualLight& l = model.lights[0];
  EXPECT_EQ(l.kind, PunctualLight::Kind::Point);
  EXPECT_NEAR(glm::length(l.position - Vec3(5, 0, 0)), 0, 1e-9);
  EXPECT_NEAR(glm::length(l.intensity - Rgb(1, 0.5, 0.25)), 0, 1e-6);
  EXPECT_TRUE(std::none_of(model.warnings.begin(), model.warnings.end(), [](const std::string& w) {
    return w.find("no material emits light") != std::string::npos;
  }));
  // Placed in a scene, the light moves with the model and lights the render.
  const nlohmann::json doc = {
      {"objects", {{{"type", "model"}, {"name", "lamp"}, {"file", (dir / "quad.gltf").string()}}}}};
  const Scene scene = parse_scene(doc);
  ASSERT_EQ(scene.lights.size(), 1u);
  EXPECT_EQ(scene.lights[0].name, "lamp/holder");  // Assimp names a light by its node
}

void write_uniform_exr(const std::filesystem::path& file, const Rgb& value) {
  Image image(4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) image.set(x, y, value);
  write_image(file, image, 1);
}

// glTF's metallic/roughness, normalTexture (with its scale) and emissiveTexture.
TEST(ModelImport, MetalNormalMapsAndEmissiveTextures) {
  const auto dir = test::fresh_temp_dir("import-pbr");
  write_uniform_exr(dir / "n.exr", Rgb(0.8, 0.5, 0.9));
  write_uniform_exr(dir / "e.exr", Rgb(0.5, 0.25, 1));
  const auto file = mirrored_quad_gltf(dir, R"({"name": "brass",
      "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.2, 1], "metallicFactor": 1,
                               "roughnessFactor": 0.5},
      "normalTexture": {"index": 0, "scale": 0.5},
      "emissiveTexture": {"index": 1}, "emissiveFactor": [2, 2, 2]})",
                                       R"(
  "textures": [{"source": 0}, {"source": 1}],
  "images": [{"uri": "n.exr"}, {"uri": "e.exr"}],)");
  const ImportedModel model = import_model(file);
  ASSERT_EQ(model.objects.size(), 1u);
  const Material& m = model.materials[std::size_t(model.objects[0].material)];
  // All metal: no diffuse part; k_s the base colour's mean, Phong n = 2 / 0.5^4 - 2 = 30.
  EXPECT_EQ(m.reflectance, Rgb(0));
  EXPECT_NEAR(m.specular, (0.8 + 0.6 + 0.2) / 3, 1e-6);
  EXPECT_NEAR(m.shininess, 30, 1e-9);
  // Emission: pi x factor x the texture's mean, with a warning that it is sent evenly; the
  // texture itself, scaled to mean 1, is what the camera sees.
  EXPECT_NEAR(glm::length(m.emission - std::numbers::pi * 2 * Rgb(0.5, 0.25, 1)), 0, 1e-3);
  ASSERT_TRUE(m.emission_texture);
  EXPECT_NEAR(glm::length(texture_mean(*m.emission_texture) - Rgb(1)), 0, 1e-6);
  EXPECT_TRUE(std::any_of(model.warnings.begin(), model.warnings.end(), [](const std::string& w) {
    return w.find(
               "material \"brass\": its emissive texture is shown, but the light it sends "
               "is its mean") != std::string::npos;
  }));
  ASSERT_EQ(model.bumps.size(), 1u);
  EXPECT_EQ(model.objects[0].bump, 0);
  const BumpFunction& n = model.bumps[0];
  EXPECT_EQ(n.name, "brass/normal");
  EXPECT_EQ(n.type, BumpType::NormalMap);
  EXPECT_EQ(n.strength, 0.5);
  ASSERT_TRUE(n.image);
  EXPECT_NEAR(n.image->at(1, 1).r, 0.8, 1e-3);  // data: read as stored
  const Scene scene = load_scene(file.string());
  ASSERT_EQ(scene.bumps.size(), 1u);
  EXPECT_EQ(scene.bumps[0].name, "quad/brass/normal");

  // glTF's defaults are metallic 1, roughness 1: a rough metal, Phong n at its floor of 1.
  const ImportedModel rough = import_model(mirrored_quad_gltf(
      dir,
      R"({"name": "plain", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1]}})"));
  const Material& r = rough.materials[std::size_t(rough.objects[0].material)];
  EXPECT_EQ(r.reflectance, Rgb(0));
  EXPECT_NEAR(r.specular, 0.5, 1e-6);
  EXPECT_EQ(r.shininess, 1);
  EXPECT_TRUE(rough.bumps.empty());
  EXPECT_EQ(rough.objects[0].bump, -1);
}

// OBJ's norm, and bump/map_Bump read as a normal map with its -bm, as Blender reads it.
TEST(ModelImport, ObjBumpMapsAreNormalMaps) {
  const auto dir = test::fresh_temp_dir("import-obj-bump");
  write_uniform_exr(dir / "n.exr", Rgb(0.5, 0.5, 1));
  std::ofstream(dir / "quad.mtl") << "newmtl tiles\nKd 0.5 0.5 0.5\nmap_Bump -bm 0.3 n.exr\n"
                                     "newmtl plaster\nKd 0.5 0.5 0.5\nnorm n.exr\n";
  std::ofstream(dir / "quad.obj") << "mtllib quad.mtl\n"
                                     "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                     "v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                     "usemtl tiles\nf 1/1 2/2 3/3 4/4\n"
                                     "usemtl plaster\nf 5/1 6/2 7/3 8/4\n";
  const ImportedModel model = import_model(dir / "quad.obj");
  ASSERT_EQ(model.bumps.size(), 2u);
  std::map<std::string, double> strength;
  for (const BumpFunction& b : model.bumps) {
    EXPECT_EQ(b.type, BumpType::NormalMap);
    strength[b.name] = b.strength;
  }
  EXPECT_NEAR(strength["tiles/normal"], 0.3, 1e-6);
  EXPECT_EQ(strength["plaster/normal"], 1);
  for (const Object& o : model.objects) EXPECT_GE(o.bump, 0) << o.name;
}

TEST(ModelImport, RealFilesKeepTheirTextureCoordinatesMaterialsAndCameras) {
  ASSERT_TRUE(std::filesystem::exists(kTestModels))
      << "scripts/setup.sh --tests installs assimp-testmodels";
  const ImportedModel box =
      import_model(kTestModels / "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb");
  ASSERT_EQ(box.objects.size(), 1u);
  const auto& shape = std::get<TriangleMeshShape>(box.objects[0].shape);
  EXPECT_EQ(shape.triangles.size(), 12u);
  EXPECT_EQ(shape.uvs.size(), shape.positions.size());
  EXPECT_EQ(shape.normals.size(), shape.positions.size());
  // Its six faces stay apart at the creases: 24 vertices, 4 a face.
  EXPECT_EQ(
      build_mesh(
          load_scene((kTestModels / "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb").string()))
          .surface_count,
      1u);

  const ImportedModel obj = import_model(kTestModels / "OBJ/box.obj");
  ASSERT_FALSE(obj.objects.empty());
  ASSERT_FALSE(obj.warnings.empty());
  EXPECT_NE(obj.warnings[0].find("has no texture coordinates"), std::string::npos);
  // Without them, (u, v) project each vertex along its normal's main axis, in units of the
  // mesh's largest extent: on the faces facing +-y, (x, z).
  const auto& projected = std::get<TriangleMeshShape>(obj.objects[0].shape);
  ASSERT_EQ(projected.uvs.size(), projected.positions.size());
  Vec3 lo = projected.positions[0], hi = lo;
  for (const Vec3& p : projected.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  int facing_y = 0;
  for (std::size_t i = 0; i < projected.positions.size(); ++i) {
    const Vec3 n = glm::abs(projected.normals[i]);
    if (n.y <= n.x || n.y <= n.z) continue;
    ++facing_y;
    EXPECT_NEAR(projected.uvs[i].x, (projected.positions[i].x - lo.x) / extent, 1e-12);
    EXPECT_NEAR(projected.uvs[i].y, (projected.positions[i].z - lo.z) / extent, 1e-12);
  }
  EXPECT_GE(facing_y, 8);  // the top and bottom faces' corners

  const ImportedModel cameras = import_model(kTestModels / "glTF2/cameras/Cameras.gltf");
  ASSERT_TRUE(cameras.camera);
  EXPECT_GT(cameras.camera->fov_y_deg, 0);
  EXPECT_LT(cameras.camera->fov_y_deg, 180);
}

std::string error_of(const std::filesystem::path& file) {
  try {
    import_model(file);
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

TEST(ModelImport, BadFilesAreRefusedNamingTheFileAndTheMesh) {
  const auto dir = test::fresh_temp_dir("import-bad");
  EXPECT_EQ(error_of(dir / "none.obj"), (dir / "none.obj").string() + ": no such file");
  std::ofstream(dir / "points.obj") << "v 0 0 0\nv 1 0 0\np 1\np 2\n";
  EXPECT_NE(error_of(dir / "points.obj").find("points.obj: No meshes remaining"), std::string::npos)
      << error_of(dir / "points.obj");
  std::ofstream(dir / "huge.obj") << "o far\nv 0 0 0\nv 1e13 0 0\nv 0 1 0\nf 1 2 3\n";
  EXPECT_NE(error_of(dir / "huge.obj").find("huge.obj: mesh \""), std::string::npos)
      << error_of(dir / "huge.obj");
  EXPECT_NE(error_of(dir / "huge.obj").find("vertex 1 is not a finite point"), std::string::npos);
  std::ofstream(dir / "junk.glb") << "not a model";
  EXPECT_NE(error_of(dir / "junk.glb").find("junk.glb: "), std::string::npos);
  EXPECT_TRUE(is_model_file("room.glb"));
  EXPECT_TRUE(is_model_file("room.OBJ"));
  EXPECT_FALSE(is_model_file("scene.json"));
}

}  // namespace
}  // namespace bumprad

namespace bumprad {
namespace {

// A copy of the glTF box whose texture file is `png` (empty: none beside it).
std::filesystem::path box_with_texture(const std::filesystem::path& dir, const std::string& png) {
  const auto source = kTestModels / "glTF2/BoxTextured-glTF";
  std::filesystem::copy_file(source / "BoxTextured.gltf", dir / "BoxTextured.gltf");
  std::filesystem::copy_file(source / "BoxTextured0.bin", dir / "BoxTextured0.bin");
  if (!png.empty()) test::write_file(dir / "CesiumLogoFlat.png", png);
  return dir / "BoxTextured.gltf";
}

// glTF's base colour texture, embedded (.glb) or beside the file (.gltf), sRGB decoded and
// times the base colour factor: the material's texture, its mean the solve's reflectance.
TEST(ModelImport, BaseColourTexturesEmbeddedOrBesideTheFile) {
  const ImportedModel glb =
      import_model(kTestModels / "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb");
  const ImportedModel gltf = import_model(kTestModels / "glTF2/BoxTextured-glTF/BoxTextured.gltf");
  const Material& a = glb.materials[std::size_t(glb.objects[0].material)];
  const Material& b = gltf.materials[std::size_t(gltf.objects[0].material)];
  ASSERT_TRUE(a.texture && a.texture->image);
  ASSERT_TRUE(b.texture && b.texture->image);
  EXPECT_EQ(a.texture->image->width, b.texture->image->width);
  EXPECT_EQ(a.texture->image->rgb, b.texture->image->rgb);
  const Image decoded = read_image(kTestModels / "glTF2/BoxTextured-glTF/CesiumLogoFlat.png");
  ASSERT_EQ(decoded.rgb.size(), a.texture->image->rgb.size());
  double mean = 0;
  for (float v : decoded.rgb) mean += std::min(0.99, double(v)) / double(decoded.rgb.size());
  EXPECT_NEAR((a.reflectance.r + a.reflectance.g + a.reflectance.b) / 3, mean, 1e-6);
  EXPECT_NEAR(glm::length(a.reflectance - b.reflectance), 0, 1e-12);
}

TEST(ModelImport, MissingAndOversizedTexturesAreRefusedByName) {
  const auto missing = test::fresh_temp_dir("import-texture-missing");
  EXPECT_NE(
      error_of(box_with_texture(missing, "")).find("texture \"CesiumLogoFlat.png\" is missing"),
      std::string::npos)
      << error_of(box_with_texture(missing, ""));
  // A 68-byte PNG whose header says 20000 x 20000: refused before anything is decoded.
  const auto bomb = test::fresh_temp_dir("import-texture-bomb");
  const std::string e = error_of(box_with_texture(bomb, test::png_bomb()));
  EXPECT_NE(e.find("texture \"CesiumLogoFlat.png\": 20000 x 20000 pixels, over the limit of "
                   "67108864"),
            std::string::npos)
      << e;
  // Within the pixel limit, but past what the scene's images may take (#28 item 1).
  const auto real = test::fresh_temp_dir("import-texture-budget");
  ImageBudget budget(Limits::kMaxTexturePixels, 500'000);
  try {
    import_model(
        box_with_texture(
            real, test::read_file(kTestModels / "glTF2/BoxTextured-glTF/CesiumLogoFlat.png")),
        {}, &budget);
    FAIL() << "the texture (211 x 211) fits no budget of 500 KB";
  } catch (const ModelError& error) {
    EXPECT_NE(std::string(error.what())
                  .find("texture \"CesiumLogoFlat.png\": 211 x 211 pixels take 668 KB to "
                        "decode, over what is left of the 500 KB"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace bumprad

namespace bumprad {
namespace {

nlohmann::json scene_placing(const std::string& file) {
  return nlohmann::json::parse(R"({
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "width": 32, "height": 32},
    "materials": {"white": {"reflectance": 0.5}},
    "bumps": {"wrinkles": {"type": "wrinkles", "amplitude": 0.01}},
    "objects": [
      {"type": "quad", "material": "white",
       "vertices": [[-9, -9, -1], [9, -9, -1], [9, 9, -1], [-9, 9, -1]]},
      {"type": "model", "name": "lamp", "file": ")" +
                               file + R"(",
       "transform": {"translate": [0, 0, 2], "rotation_deg": [0, 0, 90], "scale": 2},
       "bump": "wrinkles"}
    ]})");
}

// A scene JSON places a model: scaled, turned, moved, its materials added or mapped onto the
// scene's, the object's bump on each of its meshes; every error names the field.
TEST(ModelImport, SceneJsonPlacesModels) {
  const auto dir = test::fresh_temp_dir("import-scene");
  const std::string file = mirrored_quad_gltf(dir).string();
  nlohmann::json doc = scene_placing(file);
  Scene scene = parse_scene(doc);
  ASSERT_EQ(scene.objects.size(), 2u);
  const Object& lamp = scene.objects[1];
  EXPECT_EQ(lamp.name, "lamp/mirror/quad");
  EXPECT_EQ(lamp.bump, 0);
  // The quad spans x in [4, 5], y in [0, 1] in the file; x2, turned 90 degrees about z, up 2.
  const auto& shape = std::get<TriangleMeshShape>(lamp.shape);
  for (const Vec3& p : shape.positions) {
    EXPECT_GE(p.x, -2 - 1e-9);
    EXPECT_LE(p.x, 1e-9);
    EXPECT_GE(p.y, 8 - 1e-9);
    EXPECT_LE(p.y, 10 + 1e-9);
    EXPECT_NEAR(p.z, 2, 1e-9);
  }
  EXPECT_EQ(scene.materials[std::size_t(lamp.material)].name, "glow");
  doc["objects"][1]["materials"] = {{"glow", "white"}};
  EXPECT_EQ(parse_scene(doc).objects[1].material, 0);

  const auto rejected = [&](const nlohmann::json& d) {
    try {
      parse_scene(d);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  doc["objects"][1]["materials"] = {{"neon", "white"}};
  EXPECT_EQ(rejected(doc),
            "/objects/1/materials/neon: the model has no material of this name "
            "(it has: glow, material 1)");
  doc["objects"][1]["materials"] = {{"glow", "gold"}};
  EXPECT_EQ(rejected(doc), "/objects/1/materials/glow: unknown material \"gold\"");
  doc = scene_placing(file);
  doc["objects"][1]["transform"]["scale"] = 0;
  EXPECT_EQ(rejected(doc), "/objects/1/transform/scale: must not be zero");
  doc = scene_placing((dir / "none.glb").string());
  EXPECT_EQ(rejected(doc),
            "/objects/1/file: \"" + (dir / "none.glb").string() + "\": no such file");
  // Model files resolve as image files do: a server without --assets names none.
  try {
    parse_scene(scene_placing(file), ImageFiles::refused());
    ADD_FAILURE() << "a refused file was read";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.pointer(), "/objects/1/file") << e.what();
  }
}

// A placed model's normal maps are scene bumps under its name, swapped by name as any bump
// is; on a server its textures stay inside the asset directory as its own file must.
TEST(ModelImport, PlacedNormalMapsAreNamedAndConfined) {
  namespace fs = std::filesystem;
  const auto assets = test::fresh_temp_dir("import-confined");
  fs::create_directories(assets / "lamp");
  write_uniform_exr(assets / "lamp" / "n.exr", Rgb(0.6, 0.5, 0.9));
  write_uniform_exr(assets.parent_path() / "confined-outside.exr", Rgb(0.6, 0.5, 0.9));
  const auto material = [](const std::string& uri) {
    return std::pair(std::string(R"({"name": "brass", "pbrMetallicRoughness": {"metallicFactor": 0},
                                     "normalTexture": {"index": 0}})"),
                     R"(
  "textures": [{"source": 0}], "images": [{"uri": ")" +
                         uri + R"("}],)");
  };
  auto [inside, inside_extra] = material("n.exr");
  mirrored_quad_gltf(assets / "lamp", inside, inside_extra);
  nlohmann::json doc = scene_placing("lamp/quad.gltf");
  doc["objects"][1].erase("bump");
  const ImageFiles sandbox = ImageFiles::sandbox(assets);
  Scene scene = parse_scene(doc, sandbox);
  ASSERT_EQ(scene.bumps.size(), 2u);
  EXPECT_EQ(scene.bumps[1].name, "lamp/brass/normal");
  EXPECT_EQ(scene.objects[1].bump, 1);
  apply_bump_overrides(nlohmann::json::parse(R"({"lamp/brass/normal": {"type": "dimples"}})"),
                       scene, "/bumps", sandbox);
  EXPECT_EQ(scene.bumps[1].type, BumpType::Dimples);

  auto [outside, outside_extra] = material("../../confined-outside.exr");
  mirrored_quad_gltf(assets / "lamp", outside, outside_extra);
  try {
    parse_scene(doc, sandbox);
    ADD_FAILURE() << "a texture outside the assets was read";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.pointer(), "/objects/1/file");
    EXPECT_NE(std::string(e.what()).find("texture \"../../confined-outside.exr\" lies outside the "
                                         "files this model may read"),
              std::string::npos)
        << e.what();
  }
  // From the command line (no sandbox) the same model reads its texture beside it.
  EXPECT_EQ(parse_scene(scene_placing((assets / "lamp/quad.gltf").string())).bumps.size(), 2u);
}

std::string file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::size_t temporary_file_dirs() {
  std::size_t n = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::filesystem::temp_directory_path()))
    n += entry.path().filename().string().rfind("bumprad-files-", 0) == 0;
  return n;
}

// A scene carries its model, the model's buffer and its normal map in "files": a server
// without --assets reads them, and nothing of them is left on disk after the parse.
TEST(ModelImport, AScenesOwnFilesCarryItsModels) {
  const auto dir = test::fresh_temp_dir("import-embedded");
  write_uniform_exr(dir / "n.exr", Rgb(0.6, 0.5, 0.9));
  mirrored_quad_gltf(dir, R"({"name": "brass", "pbrMetallicRoughness": {"metallicFactor": 0},
                               "normalTexture": {"index": 0}})",
                     R"(
  "textures": [{"source": 0}], "images": [{"uri": "n.exr"}],)");
  nlohmann::json doc = scene_placing("lamp/quad.gltf");
  doc["objects"][1].erase("bump");
  for (const char* name : {"quad.gltf", "quad.bin", "n.exr"})
    doc["files"][std::string("lamp/") + name] = base64_encode(file_bytes(dir / name));
  const std::size_t before = temporary_file_dirs();
  const Scene scene = parse_scene(doc, ImageFiles::refused());
  EXPECT_EQ(temporary_file_dirs(), before);
  ASSERT_EQ(scene.bumps.size(), 2u);
  EXPECT_EQ(scene.bumps[1].name, "lamp/brass/normal");
  EXPECT_NEAR(scene.bumps[1].image->at(0, 0).r, 0.6, 1e-3);

  const auto rejected = [&](const nlohmann::json& d) {
    try {
      parse_scene(d, ImageFiles::refused());
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  nlohmann::json bad = doc;
  bad["files"]["lamp/n.exr"] = "not base64!";
  EXPECT_EQ(rejected(bad),
            "/files/lamp~1n.exr: must be the file's bytes in base64 (RFC 4648, padded)");
  bad = doc;
  bad["files"]["../n.exr"] = "";
  EXPECT_NE(rejected(bad).find("/files/..~1n.exr: a file name must be a relative path without"),
            std::string::npos)
      << rejected(bad);
  bad = doc;
  bad["files"]["lamp/quad.gltf/x"] = "";
  EXPECT_NE(rejected(bad).find("clashes with another file's"), std::string::npos) << rejected(bad);
  bad = doc;
  bad["files"].erase("lamp/n.exr");
  EXPECT_NE(rejected(bad).find("texture \"n.exr\" is missing"), std::string::npos) << rejected(bad);
  EXPECT_EQ(temporary_file_dirs(), before);
}

}  // namespace
}  // namespace bumprad
