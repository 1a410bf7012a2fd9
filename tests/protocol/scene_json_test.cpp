// Every rejection rule of the scene format, each checked for the field it names and the
// reason it gives; plus the defaults a minimal scene gets.
#include "protocol/scene_json.h"

#include <sys/stat.h>

#include "solver/util/image.h"
#include "tests/test_files.h"

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace bumprad {
namespace {

using json = nlohmann::json;

json minimal() {
  return json::parse(R"({
    "camera": {"position": [0, 1, 5], "look_at": [0, 1, 0]},
    "materials": {"white": {"reflectance": 0.7}, "lamp": {"emission": [10, 10, 10]}},
    "objects": [
      {"type": "quad", "material": "white",
       "vertices": [[-1, 0, -1], [-1, 0, 1], [1, 0, 1], [1, 0, -1]]},
      {"type": "box", "material": "lamp", "center": [0, 2, 0], "size": [0.2, 0.1, 0.2]}
    ]
  })");
}

// Expects parse_scene to reject `doc` at `pointer` with a message containing `reason`.
void expect_rejected(const json& doc, const std::string& pointer, const std::string& reason,
                     const ImageFiles& files = {}) {
  try {
    parse_scene(doc, files);
    ADD_FAILURE() << "accepted; expected " << pointer << ": " << reason;
  } catch (const SceneError& e) {
    EXPECT_EQ(e.pointer(), pointer) << e.what();
    EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "one line";
  }
}

TEST(SceneJson, MinimalSceneGetsTheDefaults) {
  Scene s = parse_scene(minimal());
  EXPECT_EQ(s.camera.width, 512);
  EXPECT_EQ(s.camera.up, Vec3(0, 1, 0));
  EXPECT_EQ(s.solver.hemicube_resolution, 150);
  EXPECT_EQ(s.solver.patch_elements, 0);  // automatic
  ASSERT_EQ(s.materials.size(), 2u);
  const Material& white = s.materials[std::size_t(s.objects[0].material)];
  const Material& lamp = s.materials[std::size_t(s.objects[1].material)];
  EXPECT_EQ(white.name, "white");
  EXPECT_EQ(white.reflectance, Rgb(0.7));
  EXPECT_EQ(lamp.reflectance, Rgb(0.5));
  EXPECT_EQ(lamp.emission, Rgb(10));
  EXPECT_EQ(s.objects[0].name, "quad0");
}

TEST(SceneJson, MalformedJson) {
  try {
    parse_scene(std::string_view("{\"camera\": [1, 2"));
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.pointer(), "");
    EXPECT_NE(std::string(e.what()).find("malformed JSON at byte"), std::string::npos);
  }
}

TEST(SceneJson, DeepNestingIsRefusedWithoutCrashing) {
  std::string deep(100000, '[');
  EXPECT_THROW(parse_scene(std::string_view(deep)), SceneError);
  // Well-formed and 200,000 levels deep: building, copying or freeing this recurses once per
  // level and overflows the stack, so it must be refused while it is parsed.
  for (std::string open : {"[", "{\"a\":"}) {
    std::string nested;
    for (int i = 0; i < 200000; ++i) nested += open;
    nested += "1";
    for (int i = 0; i < 200000; ++i) nested += open == "[" ? "]" : "}";
    try {
      parse_json(nested);
      ADD_FAILURE() << "accepted";
    } catch (const MalformedJson& e) {
      EXPECT_NE(std::string(e.what()).find("nested deeper than 32"), std::string::npos) << e.what();
    }
  }
  // The limit itself is allowed: 32 levels parse.
  std::string ok = std::string(kMaxJsonDepth, '[') + std::string(kMaxJsonDepth, ']');
  EXPECT_NO_THROW(parse_json(ok));
  EXPECT_THROW(parse_json("[" + ok + "]"), MalformedJson);
}

TEST(SceneJson, UnknownKeys) {
  json d = minimal();
  d["colour"] = 1;
  expect_rejected(d, "/colour", "unknown key");
  d = minimal();
  d["camera"]["zoom"] = 2;
  expect_rejected(d, "/camera/zoom", "unknown key (expected one of: position");
  d = minimal();
  d["objects"][1]["radius"] = 2;
  expect_rejected(d, "/objects/1/radius", "unknown key for a box");
  d = minimal();
  d["materials"]["white"]["color"] = 1;
  expect_rejected(d, "/materials/white/color", "unknown key");
  // A misspelt key is named as one, whether its object is read key by key or checked first.
  d = minimal();
  d["objects"][0]["typ"] = "quad";
  d["objects"][0].erase("type");
  expect_rejected(d, "/objects/0/type",
                  "is required (the object has \"typ\": a misspelling of \"type\"?)");
  d = minimal();
  d["camera"]["exposur"] = 2;
  expect_rejected(d, "/camera/exposur",
                  "unknown key (did you mean \"exposure\"? expected one of: position");
}

TEST(SceneJson, WrongTypes) {
  json d = minimal();
  d["camera"]["position"] = "here";
  expect_rejected(d, "/camera/position", "must be an array");
  d = minimal();
  d["camera"]["position"][1] = "1";
  expect_rejected(d, "/camera/position/1", "must be a number");
  d = minimal();
  d["camera"]["width"] = 512.5;
  expect_rejected(d, "/camera/width", "must be an integer");
  d = minimal();
  d["objects"] = json::object();
  expect_rejected(d, "/objects", "must be an array");
  d = minimal();
  d["objects"][0]["flip_normals"] = 1;
  expect_rejected(d, "/objects/0/flip_normals", "must be true or false");
}

TEST(SceneJson, NonFiniteNumbers) {
  // JSON has no NaN or infinity literal; an overflowing literal is the way one arrives,
  // and the JSON reader refuses it before any field is known.
  std::string text = minimal().dump();
  text.replace(text.find("\"look_at\":[0,1,0]"), 17, "\"look_at\":[0,1e999,0]");
  try {
    parse_scene(std::string_view(text));
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.pointer(), "") << e.what();
    EXPECT_NE(std::string(e.what()).find("number overflow parsing '1e999'"), std::string::npos)
        << e.what();
  }
  // Values built in code (the server's overrides) can carry NaN: refused by field.
  json d = minimal();
  d["materials"]["lamp"]["emission"][0] = std::numeric_limits<double>::quiet_NaN();
  expect_rejected(d, "/materials/lamp/emission/0", "finite");
}

TEST(SceneJson, NegativeAndZeroSizes) {
  json d = minimal();
  d["objects"][1]["size"][2] = -0.2;
  expect_rejected(d, "/objects/1/size/2", "must be greater than 0 (got -0.2)");
  d = minimal();
  d["objects"][1] = {{"type", "sphere"}, {"material", "white"}, {"radius", 0}};
  expect_rejected(d, "/objects/1/radius", "must be greater than 0");
  d = minimal();
  d["objects"][0]["mesh"] = {{"element_size", -1}};
  expect_rejected(d, "/objects/0/mesh/element_size", "must be greater than 0");
  d = minimal();
  d["objects"][1] = {{"type", "cylinder"},
                     {"material", "white"},
                     {"base", {0, 0, 0}},
                     {"top", {0, 0, 0}},
                     {"radius", 1}};
  expect_rejected(d, "/objects/1/top", "must differ from base");
}

TEST(SceneJson, DegeneratePolygons) {
  json d = minimal();
  d["objects"][0]["vertices"][2] = {-1, 0, 1};
  expect_rejected(d, "/objects/0/vertices/2", "degenerate quad: vertex repeats vertex 1");
  d = minimal();
  d["objects"][0]["vertices"] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  expect_rejected(d, "/objects/0/vertices", "degenerate quad: zero area");
  d = minimal();
  d["objects"][0]["vertices"] = {{-1, 0, -1}, {-1, 0, 1}, {1, 0, -1}, {1, 0, 1}};
  expect_rejected(d, "/objects/0/vertices", "self-intersecting");
  d["objects"][0]["vertices"] = {{-1, 0, -1}, {-1, 0, 1}, {-0.5, 0, 0.2}, {1, 0, -1}};
  expect_rejected(d, "/objects/0/vertices/2", "not convex");
  d = minimal();
  d["objects"][0]["vertices"][2] = {1, 0.5, 1};
  expect_rejected(d, "/objects/0/vertices/0", "quad is not planar");
  d = minimal();
  d["objects"][0] = {{"type", "mesh"},
                     {"material", "white"},
                     {"positions", {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}},
                     {"triangles", {{0, 1, 2}}}};
  expect_rejected(d, "/objects/0/triangles/0", "degenerate triangle: zero area");
  d["objects"][0]["triangles"] = {{0, 1, 3}};
  expect_rejected(d, "/objects/0/triangles/0/2", "must be between 0 and 2 (got 3)");
  d["objects"][0]["positions"] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  d["objects"][0]["triangles"] = {{0, 1, 2}};
  d["objects"][0]["uvs"] = {{0, 0}, {1, 0}};
  expect_rejected(d, "/objects/0/uvs", "must have exactly 3 entries (got 2)");
  d["objects"][0]["uvs"] = {{0, 0}, {1, 0}, {0, "one"}};
  expect_rejected(d, "/objects/0/uvs/2/1", "must be a number");
  d["objects"][0]["uvs"] = {{0, 0}, {1, 0}, {0, 1}};
  EXPECT_EQ(std::get<TriangleMeshShape>(parse_scene(d).objects[0].shape).uvs[2], glm::dvec2(0, 1));
}

TEST(SceneJson, ReflectanceMustStayBelowOne) {
  json d = minimal();
  d["materials"]["white"]["reflectance"] = {0.5, 1.0, 0.5};
  expect_rejected(d, "/materials/white/reflectance/1", "must be in [0, 1) (got 1)");
  d = minimal();
  d["materials"]["white"]["specular"] = 0.4;
  expect_rejected(d, "/materials/white/specular", "reflectance + specular must not exceed 1");
  d["materials"]["white"]["specular"] = 0.3;  // k_d + k_s = 1 is allowed (the paper's mirror)
  EXPECT_NO_THROW(parse_scene(d));
  d = minimal();
  d["materials"]["lamp"]["emission"] = -1;
  expect_rejected(d, "/materials/lamp/emission", "must be in [0");
}

TEST(SceneJson, MissingFieldsAndMaterials) {
  // Without a camera, one is framed on the scene: its image size and field of view are the
  // defaults, and it looks at the centre of the scene's bounds.
  json d = minimal();
  d.erase("camera");
  const Scene framed = parse_scene(d);
  EXPECT_EQ(framed.camera.width, Camera{}.width);
  EXPECT_EQ(framed.camera.fov_y_deg, Camera{}.fov_y_deg);
  EXPECT_NE(framed.camera.position, framed.camera.look_at);
  d = minimal();
  d["objects"][0].erase("material");
  expect_rejected(d, "/objects/0/material", "is required");
  d = minimal();
  d["objects"][1]["material"] = "gold";
  expect_rejected(d, "/objects/1/material", "unknown material \"gold\"");
  d = minimal();
  d["objects"][1]["type"] = "torus";
  expect_rejected(d, "/objects/1/type", "unknown object type \"torus\"");
  d = minimal();
  d["objects"] = json::array();
  expect_rejected(d, "/objects", "must have between 1 and");
}

TEST(SceneJson, Limits) {
  json d = minimal();
  d["solver"] = {{"hemicube_resolution", 2048}};
  expect_rejected(d, "/solver/hemicube_resolution", "must be between 16 and 1024");
  d["solver"] = {{"hemicube_resolution", 151}};
  expect_rejected(d, "/solver/hemicube_resolution", "must be even");
  d = minimal();
  d["camera"]["width"] = 10000;
  expect_rejected(d, "/camera/width", "must be between 1 and 8192");
  d = minimal();
  d["solver"] = {{"max_shots", 0}};
  expect_rejected(d, "/solver/max_shots", "must be between 1 and");
  d = minimal();
  d["objects"][0]["mesh"] = {{"element_size", 0.001}};
  expect_rejected(d, "/objects/0", "more than 2000000 elements");
  d = minimal();
  d["camera"]["position"][2] = 5e200;  // would overflow squares and cross products
  expect_rejected(d, "/camera/position/2", "must be within +-1e+12 (got 5e+200)");
  d = minimal();
  d["objects"][1]["size"][0] = 1e13;
  expect_rejected(d, "/objects/1/size/0", "must be within +-1e+12");
  d = minimal();
  d["objects"][0]["mesh"] = {{"elements", {5000, 1}}};
  expect_rejected(d, "/objects/0/mesh/elements/0", "must be between 1 and 4096");
}

TEST(SceneJson, CameraGeometry) {
  json d = minimal();
  d["camera"]["look_at"] = {0, 1, 5};
  expect_rejected(d, "/camera/look_at", "must differ from position");
  d = minimal();
  d["camera"]["look_at"] = {0, 0, 5};
  expect_rejected(d, "/camera", "parallel to the view direction");
  d = minimal();
  d["camera"]["fov_deg"] = 180;
  expect_rejected(d, "/camera/fov_deg", "between 0 and 180");
}

TEST(SceneJson, BumpFunctions) {
  json d = minimal();
  d["bumps"] = {{"w", {{"type", "wrinkles"}, {"amplitude", 0.01}, {"scale", {4, 8}}}}};
  d["objects"][0]["bump"] = "w";
  Scene s = parse_scene(d);
  ASSERT_EQ(s.bumps.size(), 1u);
  EXPECT_EQ(s.objects[0].bump, 0);
  EXPECT_EQ(s.objects[1].bump, -1);
  EXPECT_EQ(s.bumps[0].scale, glm::dvec2(4, 8));
  EXPECT_EQ(s.solver.texture, TextureMode::Shoot);

  d["objects"][1]["bump"] = "v";
  expect_rejected(d, "/objects/1/bump", "unknown bump function \"v\"");
  d = minimal();
  d["bumps"] = {{"w", {{"type", "ripples"}}}};
  expect_rejected(d, "/bumps/w/type", "unknown bump type \"ripples\"");
  d["bumps"] = {{"w", {{"type", "noise"}, {"mortar", 0.1}}}};
  expect_rejected(d, "/bumps/w/mortar", "unknown key for a noise bump");
  d["bumps"] = {{"w", {{"type", "bricks"}, {"mortar", 1.5}}}};
  expect_rejected(d, "/bumps/w/mortar", "between 0 and 1");
  d["bumps"] = {{"w", {{"type", "dimples"}, {"scale", 0}}}};
  expect_rejected(d, "/bumps/w/scale", "must be greater than 0");
  d["bumps"] = {{"w", {{"amplitude", 1}}}};
  expect_rejected(d, "/bumps/w/type", "is required");
}

std::string write_test_image(const std::string& name, float value) {
  std::string path = ::testing::TempDir() + name;
  Image img(8, 8);
  for (float& v : img.rgb) v = value;
  write_image(path, img, 1);
  return path;
}

// The server's policy: files only from inside its asset directory, or none at all.
TEST(SceneJson, ImageFilesStayInsideTheSandbox) {
  namespace fs = std::filesystem;
  fs::path assets = test::fresh_temp_dir("assets");
  fs::create_directories(assets / "maps");
  fs::copy_file(write_test_image("inside.png", 0.5), assets / "maps" / "grey.png");
  fs::path outside = write_test_image("outside.png", 0.5);
  fs::create_symlink(outside, assets / "link.png");
  json d = minimal();
  d["objects"][0]["material"] = "floor";
  auto with_file = [&](const std::string& file) {
    d["materials"]["floor"] = {{"texture", {{"type", "image"}, {"file", file}}}};
    return d;
  };
  const ImageFiles sandbox = ImageFiles::sandbox(assets);
  Scene s = parse_scene(with_file("maps/grey.png"), sandbox);
  EXPECT_NEAR(s.materials[std::size_t(s.objects[0].material)].reflectance.g, 0.5, 0.01);
  const std::string field = "/materials/floor/texture/file";
  expect_rejected(with_file("../outside.png"), field, "without \"..\"", sandbox);
  expect_rejected(with_file("maps/../../outside.png"), field, "without \"..\"", sandbox);
  expect_rejected(with_file(outside.string()), field, "inside the asset directory", sandbox);
  expect_rejected(with_file("link.png"), field, "leads outside the asset directory", sandbox);
  expect_rejected(with_file("maps/none.png"), field, "cannot read image", sandbox);
  // The file as the scene named it, never the server's path to it (#28 item 3).
  std::ofstream(assets / "maps" / "notimage.png") << "not an image";
  try {
    parse_scene(with_file("maps/notimage.png"), sandbox);
    ADD_FAILURE() << "a text file was read as an image";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot read image: maps/notimage.png"), std::string::npos)
        << e.what();
    EXPECT_EQ(std::string(e.what()).find(assets.string()), std::string::npos) << e.what();
  }
  expect_rejected(with_file(std::string("maps/grey.png\0x", 15)), field,
                  "must not contain NUL characters", sandbox);
  expect_rejected(with_file(std::string("maps/grey.png\0x", 15)), field,
                  "must not contain NUL characters");
  // Opening a FIFO blocks until a writer comes: it must never be opened.
  ASSERT_EQ(mkfifo((assets / "pipe.png").c_str(), 0644), 0);
  expect_rejected(with_file("pipe.png"), field, "is not a regular file", sandbox);
  expect_rejected(with_file("maps"), field, "is not a regular file", sandbox);
  expect_rejected(with_file("maps/grey.png"), field, "cannot be named here", ImageFiles::refused());
  d["materials"]["floor"] = {{"reflectance", 0.5}};
  d["bumps"] = {{"h", {{"type", "image"}, {"file", "maps/grey.png"}}}};
  expect_rejected(d, "/bumps/h/file", "cannot be named here", ImageFiles::refused());
}

TEST(SceneJson, ColourTextures) {
  json d = minimal();
  d["materials"]["floor"] = {
      {"texture", {{"type", "checker"}, {"colors", {{0.1, 0.2, 0.3}, 0.5}}, {"scale", 8}}}};
  d["objects"][0]["material"] = "floor";
  Scene s = parse_scene(d);
  const Material& m = s.materials[std::size_t(s.objects[0].material)];
  ASSERT_TRUE(m.texture);
  EXPECT_EQ(m.reflectance, Rgb(0.3, 0.35, 0.4));  // the mean of the two colours
  EXPECT_EQ(m.texture->scale, glm::dvec2(8));

  d["materials"]["floor"]["reflectance"] = 0.5;
  expect_rejected(d, "/materials/floor/reflectance", "give reflectance or a texture, not both");
  d["materials"]["floor"] = {{"texture", {{"type", "image"}, {"file", "/no/such.png"}}}};
  expect_rejected(d, "/materials/floor/texture/file", "cannot read image");
  d["materials"]["floor"] = {
      {"texture", {{"type", "image"}, {"file", write_test_image("white.png", 1)}}}};
  expect_rejected(d, "/materials/floor/texture", "mean reflectance must stay below 1");
  d["materials"]["floor"] = {
      {"texture",
       {{"type", "image"}, {"file", write_test_image("grey.png", 0.5)}, {"wrap", "tile"}}}};
  expect_rejected(d, "/materials/floor/texture/wrap", "unknown wrap mode \"tile\"");
  d["materials"]["floor"]["texture"]["wrap"] = "mirror";
  s = parse_scene(d);
  EXPECT_NEAR(s.materials[std::size_t(s.objects[0].material)].reflectance.g, 0.5, 0.01);
  d["materials"]["floor"] = {{"texture", {{"type", "marble"}}}};
  expect_rejected(d, "/materials/floor/texture/type", "unknown texture type \"marble\"");
}

TEST(SceneJson, ImageBumps) {
  json d = minimal();
  d["bumps"] = {{"map",
                 {{"type", "image"},
                  {"file", write_test_image("h.png", 0.25)},
                  {"wrap", "clamp"},
                  {"amplitude", 0.01}}}};
  Scene s = parse_scene(d);
  ASSERT_TRUE(s.bumps[0].image);
  EXPECT_EQ(s.bumps[0].wrap, Wrap::Clamp);
  // Heights are data: the PNG's 8-bit values as stored, not decoded from sRGB as colours are.
  EXPECT_NEAR(s.bumps[0].image->at(3, 3).r, srgb_encode(0.25), 0.5 / 255);
  d["bumps"]["map"]["file"] = "/no/such/height.png";
  expect_rejected(d, "/bumps/map/file", "cannot read image");
  // An image bomb is refused from its header, before decoding (#28 item 1).
  const std::string bomb = ::testing::TempDir() + "bomb.png";
  test::write_file(bomb, test::png_bomb());
  d["bumps"]["map"]["file"] = bomb;
  expect_rejected(d, "/bumps/map/file", "20000 x 20000 pixels, over the limit of 67108864");
  d["bumps"]["map"].erase("file");
  expect_rejected(d, "/bumps/map/file", "is required");
}

// One scene's images share one budget (#28 item 1): images each within the pixel limit are
// refused together, from the header of the one that would pass it, before it is decoded.
TEST(SceneJson, AScenesImagesShareOneMemoryBudget) {
  json d = minimal();
  d["objects"][0]["material"] = "floor";
  d["materials"]["floor"] = {
      {"texture", {{"type", "image"}, {"file", write_test_image("budget.png", 0.5)}}}};
  d["bumps"] = {{"map", {{"type", "image"}, {"file", write_test_image("budget.png", 0.5)}}}};
  ImageFiles files;
  // An 8 x 8 8-bit RGB image keeps 768 bytes of floats and takes 960 while it decodes.
  files.max_image_bytes = 768 + 960 - 1;
  expect_rejected(d, "/bumps/map/file",
                  "budget.png: 8 x 8 pixels take 1 KB to decode, over what is left of the 2 KB "
                  "one scene's images may take (1 KB taken by the images before it)",
                  files);
  files.max_image_bytes = 768 + 960;
  EXPECT_NO_THROW(parse_scene(d, files));
  // The bomb goes no further than its header, whatever the budget.
  const std::string bomb = ::testing::TempDir() + "bomb.png";
  test::write_file(bomb, test::png_bomb());
  d["bumps"]["map"]["file"] = bomb;
  files.max_image_bytes = std::size_t(1) << 40;
  expect_rejected(d, "/bumps/map/file", "20000 x 20000 pixels, over the limit of 67108864", files);
}

TEST(SceneJson, PunctualLights) {
  json d = minimal();
  d["lights"] = json::parse(R"([
    {"type": "point", "position": [0, 2, 0], "intensity": 5},
    {"type": "spot", "name": "key", "position": [1, 2, 0], "direction": [0, -2, 0],
     "intensity": [1, 2, 3], "inner_cone_deg": 10, "outer_cone_deg": 20},
    {"type": "directional", "direction": [0, -1, 1], "intensity": 2}])");
  const Scene s = parse_scene(d);
  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.lights[0].name, "light0");
  EXPECT_EQ(s.lights[0].intensity, Rgb(5));
  EXPECT_EQ(s.lights[1].direction, Vec3(0, -1, 0));
  EXPECT_EQ(s.lights[1].outer_cone_deg, 20);
  EXPECT_EQ(s.lights[2].kind, PunctualLight::Kind::Directional);
  json bad = d;
  bad["lights"][0]["type"] = "area";
  expect_rejected(bad, "/lights/0/type", "unknown light type \"area\"");
  bad = d;
  bad["lights"][1]["outer_cone_deg"] = 5;
  expect_rejected(bad, "/lights/1/outer_cone_deg", "the outer cone must be wider");
  bad = d;
  bad["lights"][2]["direction"] = {0, 0, 0};
  expect_rejected(bad, "/lights/2/direction", "must not be zero");
  bad = d;
  bad["lights"][0]["direction"] = {0, 1, 0};
  expect_rejected(bad, "/lights/0/direction", "unknown key");
  bad = d;
  bad["lights"][0]["intensity"] = -1;
  expect_rejected(bad, "/lights/0/intensity", "must be in [0");
  bad = d;
  bad["solver"] = {{"direct_light", "radiosity"}};
  expect_rejected(bad, "/lights", "punctual lights need \"direct_light\": \"exact\"");

  // A scene where nothing shines says it will render black; a light, or an emitter, is enough.
  json dark = minimal();
  for (auto& [name, m] : dark["materials"].items()) m.erase("emission");
  std::vector<std::string> warnings;
  parse_scene(dark, {}, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0],
            "/objects: nothing emits light (no emitting material, no light): the "
            "image will be black");
  warnings.clear();
  dark["lights"] = d["lights"];
  parse_scene(dark, {}, &warnings);
  EXPECT_TRUE(warnings.empty());
  parse_scene(minimal(), {}, &warnings);
  EXPECT_TRUE(warnings.empty());
}

TEST(SceneJson, NormalMaps) {
  json d = minimal();
  d["bumps"] = {{"n",
                 {{"type", "normal_map"},
                  {"file", write_test_image("n.png", 0.25)},
                  {"strength", 0.5},
                  {"scale", 4}}}};
  d["objects"][0]["bump"] = "n";
  Scene s = parse_scene(d);
  ASSERT_EQ(s.bumps.size(), 1u);
  EXPECT_EQ(s.bumps[0].type, BumpType::NormalMap);
  EXPECT_EQ(s.bumps[0].strength, 0.5);
  EXPECT_EQ(s.bumps[0].scale, glm::dvec2(4));
  EXPECT_NEAR(s.bumps[0].image->at(0, 0).b, srgb_encode(0.25), 0.5 / 255);  // as stored
  d["bumps"]["n"]["amplitude"] = 0.1;
  expect_rejected(d, "/bumps/n/amplitude", "normal_map bump");
  d["bumps"]["n"].erase("amplitude");
  d["bumps"]["n"]["strength"] = -1;
  expect_rejected(d, "/bumps/n/strength", "must be");
  d["bumps"]["n"] = {{"type", "normal_map"}};
  expect_rejected(d, "/bumps/n/file", "is required");
}

TEST(SceneJson, TextureModeAndMapSettings) {
  json d = minimal();
  d["solver"] = {
      {"texture", "gather"},
      {"map", {{"tilts_deg", {15, 30, 60}}, {"azimuths", 12}, {"self_illumination", true}}}};
  Scene s = parse_scene(d);
  EXPECT_EQ(s.solver.texture, TextureMode::Gather);
  EXPECT_EQ(s.solver.map.tilts_deg, (std::vector<double>{15, 30, 60}));
  EXPECT_EQ(s.solver.map.azimuths, 12);
  EXPECT_TRUE(s.solver.map.self_illumination);
  // Rings or azimuths imply the sampled normals; without them the map stores harmonics.
  EXPECT_EQ(s.solver.map.basis, MapBasisKind::SampledNormals);
  EXPECT_EQ(parse_scene(minimal()).solver.map.basis, MapBasisKind::SphericalHarmonics);
  d["solver"] = {{"map", {{"basis", "samples"}}}};
  EXPECT_EQ(parse_scene(d).solver.map.basis, MapBasisKind::SampledNormals);
  d["solver"] = {{"map", {{"basis", "sh"}, {"azimuths", 12}}}};
  expect_rejected(d, "/solver/map/azimuths", "applies only to \"basis\": \"samples\"");
  d["solver"] = {{"map", {{"basis", "wavelets"}}}};
  expect_rejected(d, "/solver/map/basis", "unknown map basis \"wavelets\"");
  d["solver"] = {{"texture", "bake"}};
  expect_rejected(d, "/solver/texture", "unknown texture mode \"bake\"");
  d["solver"] = {{"map", {{"tilts_deg", {30, 20}}}}};
  expect_rejected(d, "/solver/map/tilts_deg/1", "tilts must increase");
  d["solver"] = {{"map", {{"tilts_deg", {90}}}}};
  expect_rejected(d, "/solver/map/tilts_deg/0", "between 0 and 90");
  d["solver"] = {{"map", {{"azimuths", 2}}}};
  expect_rejected(d, "/solver/map/azimuths", "must be between 3 and 64");
}

TEST(SceneJson, DirectLightAndShadowRays) {
  json d = minimal();
  Scene s = parse_scene(d);
  EXPECT_EQ(s.solver.direct_light, DirectLight::Exact);
  EXPECT_EQ(s.camera.shadow_rays, 4);
  d["solver"] = {{"direct_light", "radiosity"}};
  d["camera"]["shadow_rays"] = 16;
  s = parse_scene(d);
  EXPECT_EQ(s.solver.direct_light, DirectLight::Radiosity);
  EXPECT_EQ(s.camera.shadow_rays, 16);
  d["solver"] = {{"direct_light", "traced"}};
  expect_rejected(d, "/solver/direct_light", "expected exact or radiosity");
  d["solver"] = json::object();
  d["camera"]["shadow_rays"] = 0;
  expect_rejected(d, "/camera/shadow_rays", "");
}

TEST(SceneJson, FormFactorMethodAndAdaptiveSubdivision) {
  json d = minimal();
  d["solver"] = {{"form_factors", "ray_cast"},
                 {"alias_pixels", 0},
                 {"adaptive", {{"levels", 2}, {"threshold", 0.25}}}};
  Scene s = parse_scene(d);
  EXPECT_EQ(s.solver.form_factors, FormFactorMethod::RayCast);
  EXPECT_EQ(s.solver.alias_pixels, 0);
  EXPECT_EQ(s.solver.adaptive_levels, 2);
  EXPECT_EQ(s.solver.adaptive_threshold, 0.25);
  EXPECT_EQ(parse_scene(minimal()).solver.form_factors, FormFactorMethod::Hemicube);
  d["solver"] = {{"form_factors", "monte_carlo"}};
  expect_rejected(d, "/solver/form_factors", "expected hemicube or ray_cast");
  d["solver"] = {{"alias_pixels", -1}};
  expect_rejected(d, "/solver/alias_pixels", "");
  d["solver"] = {{"adaptive", {{"levels", 5}}}};
  expect_rejected(d, "/solver/adaptive/levels", "");
  d["solver"] = {{"adaptive", {{"threshold", 0}}}};
  expect_rejected(d, "/solver/adaptive/threshold", "greater than 0");
  d["solver"] = {{"adaptive", {{"depth", 1}}}};
  expect_rejected(d, "/solver/adaptive/depth", "unknown key");
}

TEST(SceneJson, SolverOverridesUseTheSameChecks) {
  SolverSettings s;
  apply_solver_settings(json{{"max_shots", 7}, {"seed", 3}}, s);
  EXPECT_EQ(s.max_shots, 7);
  EXPECT_EQ(s.seed, 3u);
  try {
    apply_solver_settings(json{{"preview_every", -1}}, s, "/settings");
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.pointer(), "/settings/preview_every");
  }
}

}  // namespace
}  // namespace bumprad

namespace bumprad {
namespace {

// The keys the parser accepts, as its unknown-key message lists them.
std::set<std::string> accepted_keys(nlohmann::json doc, const nlohmann::json::json_pointer& at) {
  doc[at / "no_such_key"] = 1;
  try {
    parse_scene(doc);
  } catch (const SceneError& e) {
    std::string m = e.what();
    auto from = m.find("expected one of: ") + 17;
    std::stringstream list(m.substr(from, m.rfind(')') - from));
    std::set<std::string> keys;
    for (std::string k; std::getline(list, k, ',');)
      keys.insert(k.substr(k.find_first_not_of(' ')));
    return keys;
  }
  ADD_FAILURE() << "no_such_key accepted at " << at;
  return {};
}

std::set<std::string> schema_keys(const nlohmann::json& props) {
  std::set<std::string> keys;
  for (auto it = props.begin(); it != props.end(); ++it) keys.insert(it.key());
  return keys;
}

TEST(SceneSchema, ListsExactlyTheKeysTheParserAccepts) {
  std::ifstream in(std::string(BUMPRAD_SOURCE_DIR) + "/protocol/scene.schema.json");
  auto schema = nlohmann::json::parse(in);
  nlohmann::json doc = minimal();
  doc["objects"][0]["mesh"] = nlohmann::json::object();
  doc["solver"] = nlohmann::json::object();
  using ptr = nlohmann::json::json_pointer;
  EXPECT_EQ(accepted_keys(doc, ptr("")), schema_keys(schema["properties"]));
  EXPECT_EQ(accepted_keys(doc, ptr("/camera")),
            schema_keys(schema["properties"]["camera"]["properties"]));
  EXPECT_EQ(accepted_keys(doc, ptr("/materials/white")),
            schema_keys(schema["$defs"]["material"]["properties"]));
  EXPECT_EQ(accepted_keys(doc, ptr("/objects/0/mesh")),
            schema_keys(schema["$defs"]["mesh"]["properties"]));
  EXPECT_EQ(accepted_keys(doc, ptr("/solver")),
            schema_keys(schema["properties"]["solver"]["properties"]));
}

}  // namespace
}  // namespace bumprad
