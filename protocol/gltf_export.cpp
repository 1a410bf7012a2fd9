#include "protocol/gltf_export.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <numbers>
#include <tuple>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "solver/scene/texture.h"

namespace bumprad {
namespace {

using json = nlohmann::json;

// The binary chunk as it grows: each bufferView 4-byte aligned, as glTF asks.
class Buffer {
 public:
  // `target` 0: none (an image's bytes).
  json::number_unsigned_t view(const void* data, std::size_t length, int target, json& views) {
    while (bytes_.size() % 4) bytes_.push_back(0);
    const std::size_t offset = bytes_.size();
    bytes_.resize(offset + length);
    std::memcpy(bytes_.data() + offset, data, length);
    json v = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}};
    if (target) v["target"] = target;
    views.push_back(v);
    return views.size() - 1;
  }
  template <typename T>
  json::number_unsigned_t view(const std::vector<T>& data, int target, json& views) {
    return view(data.data(), data.size() * sizeof(T), target, views);
  }
  std::vector<char>& bytes() { return bytes_; }

 private:
  std::vector<char> bytes_;
};

constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
constexpr int kFloat = 5126, kUnsignedInt = 5125;

// The camera-to-world matrix of `c` in glTF's convention (looking down -z, +y up),
// column-major.
json camera_matrix(const Camera& c) {
  const Vec3 forward = glm::normalize(c.look_at - c.position);
  const Vec3 right = glm::normalize(glm::cross(forward, c.up));
  const Vec3 up = glm::cross(right, forward);
  json m = json::array();
  for (const Vec3& column : {right, up, -forward})
    m.insert(m.end(), {column.x, column.y, column.z, 0.0});
  m.insert(m.end(), {c.position.x, c.position.y, c.position.z, 1.0});
  return m;
}

json rgb(const Rgb& c) {
  return json::array({c.r, c.g, c.b});
}

json pair(glm::dvec2 v) {
  return json::array({v.x, v.y});
}

// The scene's images in the file, each once, as PNG textures: colours 8-bit sRGB, heights and
// normals 16-bit as stored; sampled bilinearly with the scene's wrap mode.
class Images {
 public:
  Images(Buffer& buffer, json& views) : buffer_(buffer), views_(views) {}
  std::size_t texture(const Image& image, bool data, Wrap wrap) {
    const auto key = std::make_tuple(&image, data, wrap);
    if (auto it = known_.find(key); it != known_.end()) return it->second;
    const std::string png =
        data ? encode_data_png(image) : encode_image(image, ImageFormat::Png, 1);
    images_.push_back({{"bufferView", buffer_.view(png.data(), png.size(), 0, views_)},
                       {"mimeType", "image/png"}});
    constexpr int kLinear = 9729, kRepeat = 10497, kClamp = 33071, kMirror = 33648;
    const int mode = wrap == Wrap::Clamp ? kClamp : wrap == Wrap::Mirror ? kMirror : kRepeat;
    samplers_.push_back(
        {{"magFilter", kLinear}, {"minFilter", kLinear}, {"wrapS", mode}, {"wrapT", mode}});
    textures_.push_back({{"source", images_.size() - 1}, {"sampler", samplers_.size() - 1}});
    return known_[key] = textures_.size() - 1;
  }
  // Into the file's JSON, when there are any.
  void add_to(json& gltf) const {
    if (images_.empty()) return;
    gltf["images"] = images_;
    gltf["samplers"] = samplers_;
    gltf["textures"] = textures_;
  }

 private:
  Buffer& buffer_;
  json& views_;
  json images_ = json::array(), samplers_ = json::array(), textures_ = json::array();
  std::map<std::tuple<const Image*, bool, Wrap>, std::size_t> known_;
};

// A bump function as the walkthrough evaluates it (docs/export.md): its parameters, and
// for image heights and normal maps the texture of its image.
json bump_json(const BumpFunction& b, Images& images) {
  static constexpr const char* kTypes[] = {"noise",   "wrinkles", "bricks", "tiles",
                                           "dimples", "cylinder", "image",  "normal_map"};
  json out = {{"name", b.name},           {"type", kTypes[int(b.type)]},
              {"amplitude", b.amplitude}, {"scale", pair(b.scale)},
              {"offset", pair(b.offset)}, {"octaves", b.octaves},
              {"seed", b.seed},           {"mortar", b.mortar},
              {"radius", b.radius},       {"direction_deg", b.direction_deg},
              {"strength", b.strength}};
  if (b.image) out["texture"] = images.texture(*b.image, true, b.wrap);
  return out;
}

json texture_json(const ColorTexture& t, Images& images) {
  json out = {{"scale", pair(t.scale)}, {"offset", pair(t.offset)}};
  if (t.kind == ColorTexture::Kind::Image) {
    out["type"] = "image";
    out["texture"] = images.texture(*t.image, false, t.wrap);
    out["mean"] = rgb(texture_mean(t));
  } else {
    out["type"] = "checker";
    out["colors"] = {rgb(t.colors[0]), rgb(t.colors[1])};
  }
  return out;
}

}  // namespace

std::string export_glb(const Scene& scene, const Solution& solution) {
  const Mesh& mesh = *solution.mesh;
  // All of the light at the vertices, as the view pass interpolates it (buried parts of
  // elements left out): radiosity B (W/m^2), and the radiance B / pi with the exposure.
  const std::vector<Rgb> b = vertex_light(scene, solution);
  const double exposure = scene.camera.exposure;
  // The vertices elements use (a mesh may keep some no element does), renumbered; a vertex
  // whose mean normal vanished (the pole of a sphere) takes an element's own.
  constexpr std::uint32_t kUnused = ~0u;
  std::vector<std::uint32_t> index(mesh.vertices.size(), kUnused);
  std::vector<std::uint32_t> used;
  std::vector<Vec3> fallback;
  std::vector<float> bump;  // per vertex: its object's bump function, or -1
  for (const Element& e : mesh.elements)
    for (int k = 0; k < e.vertex_count; ++k)
      if (std::uint32_t& i = index[e.v[std::size_t(k)]]; i == kUnused) {
        i = std::uint32_t(used.size());
        used.push_back(e.v[std::size_t(k)]);
        fallback.push_back(e.normal);
        bump.push_back(float(scene.objects[e.object].bump));
      }
  // The perturbed map, when it is in harmonics: each vertex's 18 coefficients per channel
  // (zero where a vertex has none), 54 floats and 2 of padding in 14 VEC4s.
  const PerturbedMap* map = solution.map.get();
  const bool with_map = map && map->basis().kind() == MapBasisKind::SphericalHarmonics;
  constexpr std::size_t kMapVectors = 14;
  std::vector<std::vector<float>> map_values(with_map ? kMapVectors : 0);
  const std::vector<Rgb> light = with_map ? map_light(scene, solution) : std::vector<Rgb>();
  const std::size_t terms = with_map ? map->basis().size() : 0;
  std::vector<float> position, normal, uv, color, radiosity, dpdu, dpdv;
  for (std::size_t j = 0; j < used.size(); ++j) {
    const std::uint32_t i = used[j];
    const Vertex& v = mesh.vertices[i];
    const Vec3 n = glm::length(v.normal) > 0.5 ? glm::normalize(v.normal) : fallback[j];
    for (int k = 0; k < 3; ++k) {
      position.push_back(float(v.position[k]));
      normal.push_back(float(n[k]));
      // glTF's colours lie in [0, 1]: what an image shows before its sRGB encoding.
      color.push_back(float(std::clamp(b[i][k] * exposure / std::numbers::pi, 0.0, 1.0)));
      radiosity.push_back(float(b[i][k]));
    }
    uv.push_back(float(v.uv.x));
    uv.push_back(float(v.uv.y));  // the surfaces' (u,v) are glTF's already (import keeps them)
    if (!with_map) continue;
    for (int k = 0; k < 3; ++k) {
      dpdu.push_back(float(v.dpdu[k]));
      dpdv.push_back(float(v.dpdv[k]));
    }
    std::array<float, 4 * kMapVectors> c{};
    if (const std::int32_t slot = map->slot(i); slot >= 0) {
      for (std::size_t t = 0; t < terms; ++t)
        for (std::size_t ch = 0; ch < 3; ++ch)
          c[3 * t + ch] = float(light[std::size_t(slot) * terms + t][int(ch)]);
    }
    for (std::size_t a = 0; a < kMapVectors; ++a)
      map_values[a].insert(map_values[a].end(), c.begin() + 4 * a, c.begin() + 4 * a + 4);
  }
  // The accessor's bounds are those of the floats written.
  std::array<float, 3> low, high;
  low.fill(std::numeric_limits<float>::infinity());
  high.fill(-std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < position.size(); ++i) {
    low[i % 3] = std::min(low[i % 3], position[i]);
    high[i % 3] = std::max(high[i % 3], position[i]);
  }
  // One primitive per material, over the same vertices; quads as two triangles.
  std::vector<std::vector<std::uint32_t>> indices(scene.materials.size());
  for (const Element& e : mesh.elements) {
    auto& list = indices[std::size_t(e.material)];
    list.insert(list.end(), {index[e.v[0]], index[e.v[1]], index[e.v[2]]});
    if (e.vertex_count == 4) list.insert(list.end(), {index[e.v[0]], index[e.v[2]], index[e.v[3]]});
  }

  json views = json::array(), accessors = json::array();
  Buffer buffer;
  Images images(buffer, views);
  const std::size_t count = used.size();
  auto attribute = [&](const std::vector<float>& data, const char* type, json extra = {}) {
    json a = {{"bufferView", buffer.view(data, kArrayBuffer, views)},
              {"componentType", kFloat},
              {"count", count},
              {"type", type}};
    if (!extra.is_null()) a.update(extra);
    accessors.push_back(a);
    return accessors.size() - 1;
  };
  json attributes = {
      {"POSITION", attribute(position, "VEC3", {{"min", low}, {"max", high}})},
      {"NORMAL", attribute(normal, "VEC3")},
      {"TEXCOORD_0", attribute(uv, "VEC2")},
      {"COLOR_0", attribute(color, "VEC3")},
      {"_RADIOSITY", attribute(radiosity, "VEC3")},
  };
  if (with_map) {
    attributes["_BUMP"] = attribute(bump, "SCALAR");
    attributes["_DPDU"] = attribute(dpdu, "VEC3");
    attributes["_DPDV"] = attribute(dpdv, "VEC3");
    for (std::size_t a = 0; a < kMapVectors; ++a)
      attributes["_MAP_" + std::to_string(a)] = attribute(map_values[a], "VEC4");
  }
  json primitives = json::array(), materials = json::array();
  for (std::size_t m = 0; m < indices.size(); ++m) {
    const Material& material = scene.materials[m];
    json extras = {{"reflectance", rgb(material.reflectance)},
                   {"emission", rgb(material.emission)},
                   {"specular", material.specular},
                   {"shininess", material.shininess}};
    if (material.texture) extras["texture"] = texture_json(*material.texture, images);
    materials.push_back(
        {{"name", material.name},
         {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}}},
         {"extensions", {{"KHR_materials_unlit", json::object()}}},
         {"extras", extras}});
    if (indices[m].empty()) continue;
    accessors.push_back({{"bufferView", buffer.view(indices[m], kElementArrayBuffer, views)},
                         {"componentType", kUnsignedInt},
                         {"count", indices[m].size()},
                         {"type", "SCALAR"}});
    primitives.push_back(
        {{"attributes", attributes}, {"indices", accessors.size() - 1}, {"material", m}});
  }
  // The bump functions' images join the buffer before its views and length are written.
  json bumps = json::array();
  if (with_map)
    for (const BumpFunction& f : scene.bumps) bumps.push_back(bump_json(f, images));
  while (buffer.bytes().size() % 4) buffer.bytes().push_back(0);
  const Camera& c = scene.camera;
  json gltf = {
      {"asset", {{"version", "2.0"}, {"generator", "bumprad"}}},
      {"extensionsUsed", {"KHR_materials_unlit"}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0, 1}}}}},
      {"nodes",
       {{{"name", "scene"}, {"mesh", 0}},
        {{"name", "camera"}, {"camera", 0}, {"matrix", camera_matrix(c)}}}},
      {"cameras",
       {{{"type", "perspective"},
         {"perspective",
          {{"yfov", c.fov_y_deg * std::numbers::pi / 180},
           {"aspectRatio", double(c.width) / c.height},
           {"znear", 1e-3 * mesh.diagonal()}}}}}},
      {"meshes", {{{"name", "solution"}, {"primitives", primitives}}}},
      {"materials", materials},
      {"accessors", accessors},
      {"bufferViews", views},
      {"buffers", {{{"byteLength", buffer.bytes().size()}}}},
      {"extras",
       {{"exposure", exposure},
        {"units", "COLOR_0: radiance x exposure, clamped to [0, 1]; _RADIOSITY: W/m^2"}}},
  };
  if (with_map) {
    gltf["extras"]["bumps"] = bumps;
    gltf["extras"]["map"] = {{"basis", "harmonics: bands 0, 1, 2, 4 (docs/export.md)"}};
  }
  images.add_to(gltf);
  std::string text = gltf.dump();
  while (text.size() % 4) text.push_back(' ');
  // GLB: a 12-byte header, the JSON chunk, the binary chunk (glTF 2.0 section 4.4).
  std::string out;
  auto u32 = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  const std::size_t bin = buffer.bytes().size();
  u32(0x46546C67);  // "glTF"
  u32(2);
  u32(std::uint32_t(12 + 8 + text.size() + 8 + bin));
  u32(std::uint32_t(text.size()));
  u32(0x4E4F534A);  // "JSON"
  out += text;
  u32(std::uint32_t(bin));
  u32(0x004E4942);  // "BIN"
  out.append(buffer.bytes().data(), bin);
  return out;
}

}  // namespace bumprad
