#include "protocol/scene_json.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <optional>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "common/paths.h"
#include "protocol/json_node.h"
#include "protocol/model_import.h"
#include "solver/scene/camera.h"
#include "solver/scene/geometry.h"
#include "solver/scene/mesh.h"
#include "solver/scene/texture.h"
#include "solver/util/image.h"

namespace bumprad {
namespace {

using json = nlohmann::json;

constexpr double kHuge = 1e300;

// A scale: one positive number for both axes, or [su, sv].
glm::dvec2 scale_pair(const Node& n) {
  if (n.value().is_number()) return glm::dvec2(n.positive());
  n.array(2, 2);
  return {n[0].positive(), n[1].positive()};
}

glm::dvec2 offset_pair(const Node& n) {
  n.array(2, 2);
  return {n[0].number(), n[1].number()};
}

Wrap parse_wrap(const Node& n) {
  return n.one_of<Wrap>(
      {{"repeat", Wrap::Repeat}, {"clamp", Wrap::Clamp}, {"mirror", Wrap::Mirror}}, "wrap mode");
}

// Image files are read when the scene is parsed, from where `files` allows.
std::shared_ptr<const Image> load_image_file(const Node& n, const ImageFiles& files,
                                             PixelMeaning meaning = PixelMeaning::Color) {
  std::string path = n.string();
  std::filesystem::path resolved;
  try {
    resolved = files.resolve(path);
  } catch (const std::invalid_argument& e) {
    n.fail(e.what());
  }
  try {
    auto image = std::make_shared<const Image>(read_image(resolved, files.budget, meaning));
    if (image->width < 1 || image->height < 1) n.fail("image \"" + path + "\" is empty");
    return image;
  } catch (const SceneError&) {
    throw;
  } catch (const std::exception& e) {
    // The decoder names the file it opened: on a server, a path in its asset directory.
    // Name it as the scene did.
    std::string why = e.what();
    const std::string opened = resolved.string();
    for (std::size_t at = why.find(opened); !opened.empty() && at != std::string::npos;
         at = why.find(opened, at + path.size()))
      why.replace(at, opened.size(), path);
    n.fail("cannot read image: " + why);
  }
}

ColorTexture parse_texture(const Node& n, const ImageFiles& files) {
  std::string type = n["type"].string();
  ColorTexture t;
  if (type == "checker") {
    n.allow_only({"type", "colors", "scale", "offset"}, "checker texture");
    if (auto c = n.get("colors")) {
      c->array(2, 2);
      t.colors = {(*c)[0].rgb(0, 1, true), (*c)[1].rgb(0, 1, true)};
    }
  } else if (type == "image") {
    n.allow_only({"type", "file", "wrap", "scale", "offset"}, "image texture");
    t.kind = ColorTexture::Kind::Image;
    t.image = load_image_file(n["file"], files);
    if (auto w = n.get("wrap")) t.wrap = parse_wrap(*w);
  } else {
    n["type"].fail("unknown texture type \"" + type + "\" (expected checker or image)");
  }
  if (auto v = n.get("scale")) t.scale = scale_pair(*v);
  if (auto v = n.get("offset")) t.offset = offset_pair(*v);
  return t;
}

// A whole camera, or with `base` only the keys that change it.
Camera parse_camera(const Node& n, const Camera* base = nullptr) {
  n.allow_only({"position", "look_at", "up", "fov_deg", "width", "height", "exposure", "antialias",
                "antialias_max", "max_depth", "glossy_samples", "shadow_rays"});
  Camera c = base ? *base : Camera{};
  if (!base || n.get("position")) c.position = n["position"].vec3();
  if (!base || n.get("look_at")) c.look_at = n["look_at"].vec3();
  if (auto v = n.get("up")) c.up = v->vec3();
  if (auto v = n.get("fov_deg")) {
    c.fov_y_deg = v->number();
    if (!(c.fov_y_deg > 0 && c.fov_y_deg < 180))
      v->fail("must be between 0 and 180 degrees, exclusive (got " + describe(c.fov_y_deg) + ")");
  }
  if (auto v = n.get("width")) c.width = int(v->integer(1, Limits::kMaxImageSide));
  if (auto v = n.get("height")) c.height = int(v->integer(1, Limits::kMaxImageSide));
  if (auto v = n.get("exposure")) c.exposure = v->positive();
  if (auto v = n.get("antialias")) c.antialias = int(v->integer(1, Limits::kMaxAntialias));
  if (auto v = n.get("antialias_max"))
    c.antialias_max = int(v->integer(0, Limits::kMaxAntialiasMax));
  if (auto v = n.get("max_depth")) c.max_depth = int(v->integer(0, 16));
  if (auto v = n.get("glossy_samples")) c.glossy_samples = int(v->integer(1, 256));
  if (auto v = n.get("shadow_rays")) c.shadow_rays = int(v->integer(1, 256));
  Vec3 view = c.look_at - c.position;
  if (!(glm::length(view) > 0)) n["look_at"].fail("must differ from position");
  if (!(glm::length(c.up) > 0)) n["up"].fail("must not be the zero vector");
  if (glm::length(glm::cross(glm::normalize(view), glm::normalize(c.up))) < 1e-6)
    n.get("up") ? n["up"].fail("must not be parallel to the view direction")
                : n.fail("the default up [0,1,0] is parallel to the view direction; give \"up\"");
  return c;
}

Material parse_material(const Node& n, const std::string& name, const ImageFiles& files) {
  n.allow_only({"reflectance", "emission", "specular", "shininess", "texture"});
  Material m;
  m.name = name;
  if (auto v = n.get("reflectance")) m.reflectance = v->rgb(0, 1, /*hi_open=*/true);
  if (auto v = n.get("texture")) {
    if (n.get("reflectance"))
      n["reflectance"].fail(
          "give reflectance or a texture, not both (a texture's mean is the "
          "reflectance)");
    m.texture = parse_texture(*v, files);
    m.reflectance = texture_mean(*m.texture);
    for (int c = 0; c < 3; ++c)
      if (!(m.reflectance[c] < 1))
        v->fail("the texture's mean reflectance must stay below 1 (got " +
                describe(m.reflectance[c]) + ")");
  }
  if (auto v = n.get("emission")) m.emission = v->rgb(0, kHuge, false);
  if (auto v = n.get("specular")) m.specular = v->in_range(0, 1, true);
  if (auto v = n.get("shininess")) m.shininess = v->in_range(0, 1e6, false);
  double most = std::max({m.reflectance.r, m.reflectance.g, m.reflectance.b});
  if (most + m.specular > 1)
    n[n.get("specular") ? "specular" : "reflectance"].fail(
        "reflectance + specular must not exceed 1 in any channel (got " +
        describe(most + m.specular) + ")");
  return m;
}

BumpFunction parse_bump(const Node& n, const std::string& name, const ImageFiles& files) {
  BumpFunction b;
  b.name = name;
  b.type = n["type"].one_of<BumpType>({{"noise", BumpType::Noise},
                                       {"wrinkles", BumpType::Wrinkles},
                                       {"bricks", BumpType::Bricks},
                                       {"tiles", BumpType::Tiles},
                                       {"dimples", BumpType::Dimples},
                                       {"cylinder", BumpType::Cylinder},
                                       {"image", BumpType::Image},
                                       {"normal_map", BumpType::NormalMap}},
                                      "bump type");
  std::vector<std::string_view> keys = {"type", "scale", "offset"};
  keys.push_back(b.type == BumpType::NormalMap ? "strength" : "amplitude");
  if (b.type == BumpType::Noise) keys.insert(keys.end(), {"octaves", "seed"});
  if (b.type == BumpType::Wrinkles || b.type == BumpType::Cylinder) keys.push_back("direction_deg");
  if (b.type == BumpType::Bricks || b.type == BumpType::Tiles) keys.push_back("mortar");
  if (b.type == BumpType::Dimples) keys.push_back("radius");
  if (b.type == BumpType::Image || b.type == BumpType::NormalMap)
    keys.insert(keys.end(), {"file", "wrap"});
  n.allow_only(keys, n["type"].string() + " bump");
  if (auto v = n.get("amplitude")) b.amplitude = v->in_range(0, kHuge, false);
  if (auto v = n.get("strength")) b.strength = v->in_range(0, kHuge, false);
  if (auto v = n.get("scale")) b.scale = scale_pair(*v);
  if (auto v = n.get("offset")) b.offset = offset_pair(*v);
  if (b.type == BumpType::Image || b.type == BumpType::NormalMap) {
    // Heights and normals are data, not colours: 8-bit files are read without the sRGB curve.
    b.image = load_image_file(n["file"], files, PixelMeaning::Data);
    if (auto v = n.get("wrap")) b.wrap = parse_wrap(*v);
  }
  if (auto v = n.get("octaves")) b.octaves = int(v->integer(1, 12));
  if (auto v = n.get("seed")) b.seed = std::uint32_t(v->integer(0, 0xffffffffLL));
  if (auto v = n.get("direction_deg")) b.direction_deg = v->number();
  if (auto v = n.get("mortar")) {
    b.mortar = v->number();
    if (!(b.mortar > 0 && b.mortar < 1))
      v->fail("must be between 0 and 1, exclusive (got " + describe(b.mortar) + ")");
  }
  if (auto v = n.get("radius")) {
    b.radius = v->number();
    if (!(b.radius > 0 && b.radius <= 0.5))
      v->fail("must be in (0, 0.5] (got " + describe(b.radius) + ")");
  }
  return b;
}

// A punctual light: {"type": "point" | "spot" | "directional", "position", "direction",
// "intensity", "inner_cone_deg", "outer_cone_deg"}; docs/scene-format.md.
PunctualLight parse_light(const Node& n, std::size_t index) {
  PunctualLight l;
  const std::string type = n["type"].string();
  if (type == "point") {
    n.allow_only({"type", "name", "position", "intensity"}, "point light");
  } else if (type == "spot") {
    l.kind = PunctualLight::Kind::Spot;
    n.allow_only(
        {"type", "name", "position", "direction", "intensity", "inner_cone_deg", "outer_cone_deg"},
        "spot light");
  } else if (type == "directional") {
    l.kind = PunctualLight::Kind::Directional;
    n.allow_only({"type", "name", "direction", "intensity"}, "directional light");
  } else {
    n["type"].fail("unknown light type \"" + type + "\" (expected point, spot or directional)");
  }
  l.name = n.get("name") ? n["name"].string() : "light" + std::to_string(index);
  if (l.kind != PunctualLight::Kind::Directional) l.position = n["position"].vec3();
  if (l.kind != PunctualLight::Kind::Point) {
    const Node d = n["direction"];
    const Vec3 v = d.vec3();
    if (!(glm::length(v) > 0)) d.fail("must not be zero");
    l.direction = glm::normalize(v);
  }
  l.intensity = n["intensity"].rgb(0, kHuge, false);
  if (auto v = n.get("inner_cone_deg")) l.inner_cone_deg = v->in_range(0, 90, true);
  if (auto v = n.get("outer_cone_deg")) l.outer_cone_deg = v->in_range(0, 90, false);
  if (l.kind == PunctualLight::Kind::Spot && !(l.outer_cone_deg > l.inner_cone_deg))
    n[n.get("outer_cone_deg") ? "outer_cone_deg" : "inner_cone_deg"].fail(
        "the outer cone must be wider than the inner one (inner " + describe(l.inner_cone_deg) +
        ", outer " + describe(l.outer_cone_deg) + " degrees)");
  return l;
}

MeshDensity parse_density(const Node& n) {
  n.allow_only({"element_size", "elements", "patch_elements"});
  MeshDensity d;
  if (auto v = n.get("element_size")) d.element_size = v->positive();
  if (auto v = n.get("elements")) {
    if (v->value().is_number()) {
      d.counts[0] = d.counts[1] = int(v->integer(1, Limits::kMaxGridCount));
    } else {
      v->array(2, 2);
      d.counts = {int((*v)[0].integer(1, Limits::kMaxGridCount)),
                  int((*v)[1].integer(1, Limits::kMaxGridCount))};
    }
  }
  if (auto v = n.get("patch_elements")) d.patch_elements = int(v->integer(1, 64));
  return d;
}

// A quad must be a proper, convex, nearly planar polygon: bilinear meshing folds otherwise.
QuadShape parse_quad(const Node& n) {
  Node vs = n["vertices"];
  vs.array(4, 4);
  QuadShape q;
  for (std::size_t i = 0; i < 4; ++i) q.corners[i] = vs[i].vec3();
  const auto& p = q.corners;
  double scale = std::max(glm::length(p[2] - p[0]), glm::length(p[3] - p[1]));
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = i + 1; j < 4; ++j)
      if (!(glm::length(p[i] - p[j]) > 1e-9 * scale))
        vs[j].fail("degenerate quad: vertex repeats vertex " + std::to_string(i));
  Vec3 normal = glm::cross(p[2] - p[0], p[3] - p[1]);
  if (!(glm::length(normal) > 1e-12 * scale * scale))
    vs.fail("degenerate quad: zero area, or self-intersecting");
  normal = glm::normalize(normal);
  for (std::size_t i = 0; i < 4; ++i) {
    Vec3 turn = glm::cross(p[(i + 1) % 4] - p[i], p[(i + 2) % 4] - p[(i + 1) % 4]);
    if (glm::dot(turn, normal) <= 0)
      vs[(i + 1) % 4].fail("degenerate quad: not convex, or vertices out of order");
  }
  Vec3 mid = (p[0] + p[1] + p[2] + p[3]) / 4.0;
  for (std::size_t i = 0; i < 4; ++i) {
    double off = std::abs(glm::dot(p[i] - mid, normal));
    if (off > 0.01 * scale)
      vs[i].fail("quad is not planar: vertex lies " + describe(off) +
                 " off the mean plane (at most 1% of the diagonal is allowed)");
  }
  return q;
}

TriangleMeshShape parse_triangle_mesh(const Node& n) {
  TriangleMeshShape m;
  Node ps = n["positions"];
  std::size_t np = ps.array(3, 3 * std::size_t(Limits::kMaxElements));  // three a triangle
  for (std::size_t i = 0; i < np; ++i) m.positions.push_back(ps[i].vec3());
  Node ts = n["triangles"];
  std::size_t nt = ts.array(1, std::size_t(Limits::kMaxElements));
  for (std::size_t i = 0; i < nt; ++i) {
    Node t = ts[i];
    t.array(3, 3);
    std::array<std::uint32_t, 3> tri;
    for (std::size_t k = 0; k < 3; ++k) tri[k] = std::uint32_t(t[k].integer(0, (long long)np - 1));
    if (degenerate_triangle(m.positions[tri[0]], m.positions[tri[1]], m.positions[tri[2]]))
      t.fail("degenerate triangle: zero area");
    m.triangles.push_back(tri);
  }
  if (auto v = n.get("smooth")) m.smooth = v->boolean();
  if (auto v = n.get("uvs")) {
    v->array(np, np);  // one [u, v] per position
    for (std::size_t i = 0; i < np; ++i) {
      Node uv = (*v)[i];
      uv.array(2, 2);
      m.uvs.push_back({uv[0].within_limit(uv[0].number()), uv[1].within_limit(uv[1].number())});
    }
  }
  return m;
}

Object parse_object(const Node& n, std::size_t index,
                    const std::map<std::string, int>& material_ids,
                    const std::map<std::string, int>& bump_ids) {
  std::string type = n["type"].string();
  auto allow = [&](std::initializer_list<std::string_view> own) {
    std::vector<std::string_view> keys = {"type",         "name", "material",
                                          "flip_normals", "mesh", "bump"};
    keys.insert(keys.end(), own);
    n.allow_only(keys, type);
  };
  Object o;
  o.name = n.get("name") ? n["name"].string() : type + std::to_string(index);
  std::string material = n["material"].string();
  auto it = material_ids.find(material);
  if (it == material_ids.end()) n["material"].fail("unknown material \"" + material + "\"");
  o.material = it->second;
  if (auto v = n.get("flip_normals")) o.flip_normals = v->boolean();
  if (auto v = n.get("mesh")) o.density = parse_density(*v);
  if (auto v = n.get("bump")) {
    std::string bump = v->string();
    auto b = bump_ids.find(bump);
    if (b == bump_ids.end()) v->fail("unknown bump function \"" + bump + "\"");
    o.bump = b->second;
  }

  if (type == "quad") {
    allow({"vertices"});
    o.shape = parse_quad(n);
  } else if (type == "box") {
    allow({"center", "size", "rotation_deg"});
    BoxShape b;
    if (auto v = n.get("center")) b.center = v->vec3();
    Node size = n["size"];
    size.array(3, 3);
    b.size = {size[0].positive(), size[1].positive(), size[2].positive()};
    if (auto v = n.get("rotation_deg")) b.rotation_deg = v->vec3();
    o.shape = b;
  } else if (type == "sphere") {
    allow({"center", "radius"});
    SphereShape s;
    if (auto v = n.get("center")) s.center = v->vec3();
    s.radius = n["radius"].positive();
    o.shape = s;
  } else if (type == "cylinder") {
    allow({"base", "top", "radius", "caps"});
    CylinderShape c;
    c.base = n["base"].vec3();
    c.top = n["top"].vec3();
    c.radius = n["radius"].positive();
    if (!(glm::length(c.top - c.base) > 1e-9 * c.radius)) n["top"].fail("must differ from base");
    if (auto v = n.get("caps")) c.caps = v->boolean();
    o.shape = c;
  } else if (type == "mesh") {
    allow({"positions", "triangles", "smooth", "uvs"});
    o.shape = parse_triangle_mesh(n);
  } else {
    n["type"].fail("unknown object type \"" + type +
                   "\" (expected quad, box, sphere, cylinder, mesh or model)");
  }
  return o;
}

}  // namespace

void apply_solver_settings(const json& settings, SolverSettings& s, const std::string& pointer) {
  Node n(settings, pointer);
  n.allow_only({"hemicube_resolution", "max_shots", "unshot_fraction", "tolerance", "element_size",
                "patch_elements", "preview_every", "rotate_hemicube", "seed", "texture", "map",
                "form_factors", "alias_pixels", "adaptive", "direct_light"});
  if (auto v = n.get("hemicube_resolution")) {
    s.hemicube_resolution = int(v->integer(Limits::kMinHemicube, Limits::kMaxHemicube));
    if (s.hemicube_resolution % 2)
      v->fail("must be even (the side faces are half faces); got " +
              std::to_string(s.hemicube_resolution));
  }
  if (auto v = n.get("max_shots")) s.max_shots = int(v->integer(1, Limits::kMaxShots));
  if (auto v = n.get("unshot_fraction")) s.unshot_fraction = v->in_range(0, 1, true);
  if (auto v = n.get("tolerance")) s.tolerance = v->in_range(0, 1, true);
  if (auto v = n.get("element_size")) s.element_size = v->positive();
  if (auto v = n.get("patch_elements")) s.patch_elements = int(v->integer(1, 64));
  if (auto v = n.get("preview_every")) s.preview_every = int(v->integer(1, Limits::kMaxShots));
  if (auto v = n.get("rotate_hemicube")) s.rotate_hemicube = v->boolean();
  if (auto v = n.get("seed")) s.seed = std::uint32_t(v->integer(0, 0xffffffffLL));
  if (auto v = n.get("form_factors"))
    s.form_factors = v->one_of<FormFactorMethod>(
        {{"hemicube", FormFactorMethod::Hemicube}, {"ray_cast", FormFactorMethod::RayCast}},
        "form factor method");
  if (auto v = n.get("alias_pixels")) s.alias_pixels = v->in_range(0, 1024, false);
  if (auto v = n.get("adaptive")) {
    v->allow_only({"levels", "threshold"});
    if (auto l = v->get("levels")) s.adaptive_levels = int(l->integer(0, 4));
    if (auto t = v->get("threshold")) {
      s.adaptive_threshold = t->in_range(0, 1, true);
      if (!(s.adaptive_threshold > 0)) t->fail("must be greater than 0");
    }
  }
  if (auto v = n.get("texture"))
    s.texture = v->one_of<TextureMode>({{"none", TextureMode::None},
                                        {"gather", TextureMode::Gather},
                                        {"shoot", TextureMode::Shoot}},
                                       "texture mode");
  if (auto v = n.get("direct_light"))
    s.direct_light = v->one_of<DirectLight>(
        {{"exact", DirectLight::Exact}, {"radiosity", DirectLight::Radiosity}}, "direct light");
  if (auto v = n.get("map")) {
    v->allow_only({"basis", "tilts_deg", "azimuths", "self_illumination"});
    // Rings or azimuths ask for the sampled normals; a scene written before spherical
    // harmonics became the default keeps its meaning.
    auto tilts = v->get("tilts_deg"), azimuths = v->get("azimuths");
    s.map.basis =
        tilts || azimuths ? MapBasisKind::SampledNormals : MapBasisKind::SphericalHarmonics;
    if (auto b = v->get("basis")) {
      s.map.basis = b->one_of<MapBasisKind>(
          {{"sh", MapBasisKind::SphericalHarmonics}, {"samples", MapBasisKind::SampledNormals}},
          "map basis");
      if (s.map.basis == MapBasisKind::SphericalHarmonics && (tilts || azimuths))
        (tilts ? *tilts : *azimuths).fail("applies only to \"basis\": \"samples\"");
    }
    if (auto t = tilts) {
      std::size_t count = t->array(1, 8);
      s.map.tilts_deg.clear();
      for (std::size_t i = 0; i < count; ++i) {
        double tilt = (*t)[i].number();
        if (!(tilt > 0 && tilt < 90)) (*t)[i].fail("must be between 0 and 90 degrees, exclusive");
        if (i > 0 && !(tilt > s.map.tilts_deg.back())) (*t)[i].fail("tilts must increase");
        s.map.tilts_deg.push_back(tilt);
      }
    }
    if (azimuths) s.map.azimuths = int(azimuths->integer(3, 64));
    if (auto i = v->get("self_illumination")) s.map.self_illumination = i->boolean();
  }
}

void apply_bump_overrides(const json& bumps, Scene& scene, const std::string& pointer,
                          const ImageFiles& outside) {
  ImageBudget budget(Limits::kMaxTexturePixels, outside.max_image_bytes);
  ImageFiles files = outside;
  files.budget = &budget;
  Node n(bumps, pointer);
  for (auto it = n.object().begin(); it != bumps.end(); ++it) {
    Node b(*it, pointer + "/" + escape_token(it.key()));
    auto known = std::find_if(scene.bumps.begin(), scene.bumps.end(),
                              [&](const BumpFunction& f) { return f.name == it.key(); });
    if (known == scene.bumps.end()) {
      std::string names;
      for (const BumpFunction& f : scene.bumps) names += (names.empty() ? "" : ", ") + f.name;
      b.fail("the scene has no bump function of this name (it has: " +
             (names.empty() ? std::string("none") : names) + ")");
    }
    *known = parse_bump(b, it.key(), files);
  }
}

// A model file placed in the scene (docs/import.md): its meshes moved by "transform"
// (scale, then rotation_deg about x, y, z as boxes turn, then translate), its materials added
// to the scene's unless "materials" maps a model material's name to a scene material, the
// object's "bump" and "mesh" applied to every mesh. The file resolves as image files do.
// Returns the model's camera, placed; its warnings join `warnings`.
std::optional<Camera> add_model(const Node& n, std::size_t index,
                                const std::map<std::string, int>& material_ids,
                                const std::map<std::string, int>& bump_ids, const ImageFiles& files,
                                Scene& scene, std::vector<std::string>& warnings) {
  n.allow_only({"type", "name", "file", "transform", "materials", "bump", "mesh", "flip_normals"},
               "model");
  const Node file = n["file"];
  ImportedModel model;
  try {
    const std::filesystem::path resolved = files.resolve(file.string());
    model = import_model(resolved, files.confinement(file.string()), files.budget);
  } catch (const std::invalid_argument& e) {
    file.fail(e.what());
  } catch (const ModelError& e) {
    // The message starts with the resolved path, which may be the server's: name the file as
    // the request did.
    const std::string why = e.what();
    const std::size_t colon = why.find(": ");
    file.fail("\"" + file.string() +
              "\": " + (colon == std::string::npos ? why : why.substr(colon + 2)));
  }
  if (auto t = n.get("transform")) {
    t->allow_only({"translate", "rotation_deg", "scale"}, "transform");
    glm::dmat4 m(1);
    if (auto v = t->get("translate")) m = glm::translate(m, v->vec3());
    if (auto v = t->get("rotation_deg")) m = rotated_about_axes(m, v->vec3());
    if (auto v = t->get("scale")) {
      Vec3 k;
      if (v->value().is_number()) {
        const double uniform = v->number();
        k = Vec3(uniform);
      } else {
        k = v->vec3();
      }
      for (int c = 0; c < 3; ++c)
        if (!(std::abs(k[c]) > 0)) v->fail("must not be zero");
      m = glm::scale(m, k);
    }
    try {
      transform_model(model, m);
    } catch (const ModelError& e) {
      t->fail(e.what());
    }
  }
  // The model's materials, each replaced by a scene material where "materials" says so.
  std::vector<int> ids;
  for (const Material& material : model.materials) {
    ids.push_back(int(scene.materials.size()));
    scene.materials.push_back(material);
  }
  if (auto map = n.get("materials"))
    for (auto it = map->object().begin(); it != map->value().end(); ++it) {
      const Node target(*it, map->pointer() + "/" + escape_token(it.key()));
      auto found = std::find_if(model.materials.begin(), model.materials.end(),
                                [&](const Material& m) { return m.name == it.key(); });
      if (found == model.materials.end()) {
        std::string names;
        for (const Material& m : model.materials) names += (names.empty() ? "" : ", ") + m.name;
        target.fail("the model has no material of this name (it has: " + names + ")");
      }
      const auto scene_material = material_ids.find(target.string());
      if (scene_material == material_ids.end())
        target.fail("unknown material \"" + target.string() + "\"");
      ids[std::size_t(found - model.materials.begin())] = scene_material->second;
    }
  // Names under the object's "name", else the file's stem (the index added if another
  // object took it), so a bare model file's normal maps read "room/Brick/normal".
  std::string name =
      n.get("name") ? n["name"].string() : std::filesystem::path(file.string()).stem().string();
  if (!n.get("name") &&
      std::any_of(scene.objects.begin(), scene.objects.end(),
                  [&](const Object& o) { return o.name.rfind(name + "/", 0) == 0; }))
    name += "-" + std::to_string(index);
  const std::string prefix = name + "/";
  // The model's normal maps join the scene's bumps under the object's prefix, so a
  // re-texture can name one ("lamp/Brass/normal") to swap it.
  const int first_bump = int(scene.bumps.size());
  for (BumpFunction& b : model.bumps) {
    b.name = prefix + b.name;
    scene.bumps.push_back(std::move(b));
  }
  for (PunctualLight& l : model.lights) {
    l.name = prefix + l.name;
    scene.lights.push_back(std::move(l));
  }
  for (Object& o : model.objects) {
    o.name = prefix + o.name;
    o.material = ids[std::size_t(o.material)];
    if (o.bump >= 0) o.bump += first_bump;
    if (auto v = n.get("flip_normals")) o.flip_normals = v->boolean();
    if (auto v = n.get("mesh")) o.density = parse_density(*v);
    if (auto v = n.get("bump")) {
      auto b = bump_ids.find(v->string());
      if (b == bump_ids.end()) v->fail("unknown bump function \"" + v->string() + "\"");
      o.bump = b->second;
    }
    scene.objects.push_back(std::move(o));
  }
  // The importer names the resolved path; the request named the file.
  for (std::string& w : model.warnings)
    warnings.push_back(n.pointer() + ": \"" + file.string() + "\"" +
                       w.substr(std::min(w.size(), w.find(": "))));
  return model.camera;
}

Scene parse_scene(const json& document, const ImageFiles& outside,
                  std::vector<std::string>* warnings) {
  Node root(document, "");
  root.allow_only({"version", "description", "files", "camera", "materials", "bumps", "objects",
                   "lights", "solver"});
  // The scene's own files, where its names look first, for as long as this parse.
  std::optional<EmbeddedFiles> embedded;
  ImageBudget budget(Limits::kMaxTexturePixels, outside.max_image_bytes);
  ImageFiles files = outside;
  files.budget = &budget;
  if (auto v = root.get("files")) files.embedded = &embedded.emplace(v->value(), v->pointer());
  if (auto v = root.get("version"); v && v->integer(1, 1) != 1) v->fail("unsupported version");
  if (auto v = root.get("description")) v->string();

  Scene scene;
  if (auto v = root.get("camera")) scene.camera = parse_camera(*v);
  std::optional<Camera> model_camera;
  std::vector<std::string> model_warnings;

  std::map<std::string, int> material_ids;
  // Optional: placed models bring their own.
  if (auto materials = root.get("materials"))
    for (auto it = materials->object().begin(); it != materials->value().end(); ++it) {
      Node m(*it, materials->pointer() + "/" + escape_token(it.key()));
      material_ids[it.key()] = int(scene.materials.size());
      scene.materials.push_back(parse_material(m, it.key(), files));
    }

  std::map<std::string, int> bump_ids;
  if (auto bumps = root.get("bumps"))
    for (auto it = bumps->object().begin(); it != bumps->value().end(); ++it) {
      Node b(*it, bumps->pointer() + "/" + escape_token(it.key()));
      bump_ids[it.key()] = int(scene.bumps.size());
      scene.bumps.push_back(parse_bump(b, it.key(), files));
    }

  Node objects = root["objects"];
  std::size_t n = objects.array(1, std::size_t(Limits::kMaxElements));
  std::vector<std::size_t> from;  // per scene object, its entry in "objects"
  for (std::size_t i = 0; i < n; ++i) {
    if (objects[i].get("type") && objects[i]["type"].value() == "model") {
      auto camera = add_model(objects[i], i, material_ids, bump_ids, files, scene, model_warnings);
      if (!model_camera) model_camera = camera;
    } else
      scene.objects.push_back(parse_object(objects[i], i, material_ids, bump_ids));
    from.resize(scene.objects.size(), i);
  }

  if (auto v = root.get("lights")) {
    const std::size_t count = v->array(0, 1000);
    for (std::size_t i = 0; i < count; ++i) scene.lights.push_back(parse_light((*v)[i], i));
  }

  if (auto v = root.get("solver")) apply_solver_settings(v->value(), scene.solver, v->pointer());
  // A point has no area for a hemi-cube or the map to see: its light is exact per pixel.
  if (!scene.lights.empty() && scene.solver.direct_light != DirectLight::Exact)
    root["lights"].fail("punctual lights need \"direct_light\": \"exact\" (the default)");

  // Refuse oversized meshes before any memory is spent on them.
  const std::vector<double> sizes = object_element_sizes(scene);
  std::size_t total = 0;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    total += estimate_element_count(scene.objects[i], sizes[i]);
    if (total > std::size_t(Limits::kMaxElements))
      objects[from[i]].fail("the scene would mesh into more than " +
                            std::to_string(Limits::kMaxElements) +
                            " elements; raise element_size (per object under \"mesh\", or in "
                            "\"solver\")");
  }
  // Nothing that shines renders black: say so (models often bring no light of their own).
  const bool shines = !scene.lights.empty() ||
                      std::any_of(scene.objects.begin(), scene.objects.end(), [&](const Object& o) {
                        return scene.materials[std::size_t(o.material)].emission != Rgb(0);
                      });
  if (!shines)
    model_warnings.push_back(
        "/objects: nothing emits light (no emitting material, no light): the image will be black");
  // Without a "camera": the first placed model's own, else one framed on the scene.
  if (!root.get("camera"))
    scene.camera = model_camera ? *model_camera : framed_camera(build_mesh(scene), scene.camera);
  if (warnings) warnings->insert(warnings->end(), model_warnings.begin(), model_warnings.end());
  return scene;
}

Scene parse_scene(std::string_view text, const ImageFiles& files,
                  std::vector<std::string>* warnings) {
  return parse_scene(parse_json(text), files, warnings);
}

Camera parse_camera_changes(const json& changes, const Camera& base, const std::string& pointer) {
  return parse_camera(Node(changes, pointer), &base);
}

std::filesystem::path ImageFiles::resolve(const std::string& name) const {
  // A path stops at a NUL: "good.png\0x" would open good.png.
  if (name.find('\0') != std::string::npos)
    throw std::invalid_argument("a file name must not contain NUL characters");
  if (embedded && embedded->contains(name)) return embedded->dir() / name;
  switch (access) {
    case Access::WorkingDirectory:
      return name;
    case Access::Refused:
      throw std::invalid_argument(
          "image files cannot be named here (this server was started without --assets)");
    case Access::Sandbox:
      break;
  }
  std::filesystem::path relative(name);
  bool escapes = relative.empty() || relative.is_absolute() || relative.has_root_name();
  for (const auto& part : relative) escapes = escapes || part == "..";
  if (escapes)
    throw std::invalid_argument("\"" + name +
                                "\" must be a path inside the asset directory, without \"..\"");
  // Symbolic links inside the sandbox must not lead out of it either.
  if (!lies_inside(root, root / relative))
    throw std::invalid_argument("\"" + name + "\" leads outside the asset directory");
  const auto full = std::filesystem::weakly_canonical(root / relative);
  // Opening a FIFO or a device would block, or never end: only regular files are read.
  std::error_code error;
  auto status = std::filesystem::status(full, error);
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    throw std::invalid_argument("\"" + name + "\" is not a regular file in the asset directory");
  return full;
}

std::optional<std::filesystem::path> ImageFiles::confinement(const std::string& name) const {
  if (embedded && embedded->contains(name)) return embedded->dir();
  if (access == Access::Sandbox) return root;
  return std::nullopt;
}

}  // namespace bumprad
