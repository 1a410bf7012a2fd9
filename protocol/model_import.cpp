#include "protocol/model_import.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <string_view>
#include <utility>

#include <assimp/GltfMaterial.h>
#include <assimp/ObjMaterial.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "common/paths.h"
#include "protocol/gltf_json.h"
#include "solver/scene/geometry.h"
#include "solver/scene/mesh.h"
#include "solver/scene/texture.h"
#include "solver/util/image.h"

namespace bumprad {
namespace {

// Reflectances stay below 1 (the solve would not converge); a white base colour of 1.0 is
// read as this.
constexpr double kMaxReflectance = 0.99;

Vec3 vec(const aiVector3D& v) {
  return {v.x, v.y, v.z};
}

// A tangent and its handedness w, +1 where the bitangent lies along normal x tangent, -1
// where against it (glTF's TANGENT), from a tangent and bitangent carried through a transform.
glm::dvec4 with_handedness(const Vec3& normal, const Vec3& tangent, const Vec3& bitangent) {
  return {tangent, glm::dot(glm::cross(normal, tangent), bitangent) < 0 ? -1.0 : 1.0};
}

// The corners of the box around a mesh's positions (there is at least one).
std::pair<Vec3, Vec3> bounds(const TriangleMeshShape& m) {
  Vec3 lo = m.positions.front(), hi = lo;
  for (const Vec3& p : m.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return {lo, hi};
}

bool finite_within_limit(const Vec3& p) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(p[k]) || std::abs(p[k]) > Limits::kMaxMagnitude) return false;
  return true;
}

class Reader {
 public:
  Reader(const std::filesystem::path& file, const aiScene& scene,
         const std::optional<std::filesystem::path>& confine, ImageBudget* budget)
      : file_(file),
        scene_(scene),
        confine_(confine),
        budget_(budget ? budget : &own_budget_),
        obj_(file.extension() == ".obj") {}

  ImportedModel read() {
    if (is_gltf_file(file_)) try {
        gltf_ = read_gltf_json(file_);
      } catch (const std::exception& e) {
        fail(e.what());
      }
    for (unsigned i = 0; i < scene_.mNumMaterials; ++i) read_material(*scene_.mMaterials[i], i);
    if (model_.materials.empty()) {
      Material fallback;
      fallback.name = "default";
      model_.materials.push_back(fallback);
      material_bump_.push_back(-1);
      material_two_sided_.push_back(false);
    }
    visit(*scene_.mRootNode, aiMatrix4x4());
    if (model_.objects.empty()) fail("it has no triangles (points and lines are not rendered)");
    // About the materials meshes use: a file's unused ones (Assimp's own default) say nothing.
    std::vector<bool> used(model_.materials.size());
    for (const Object& o : model_.objects) used[std::size_t(o.material)] = true;
    for (std::size_t m = 0; m < material_warnings_.size(); ++m)
      if (used[m])
        for (const std::string& w : material_warnings_[m]) warn(w);
    if (dropped_) warn(std::to_string(dropped_) + " degenerate triangles dropped");
    if (!without_uvs_.empty())
      warn((without_uvs_.size() == 1 ? "mesh \"" + without_uvs_[0] + "\" has"
                                     : std::to_string(without_uvs_.size()) + " meshes (\"" +
                                           without_uvs_[0] + "\", ...) have") +
           " no texture coordinates: bump functions use a projection along the normals' main "
           "axes (docs/import.md)");
    read_lights();
    read_camera();
    return std::move(model_);
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw ModelError(file_.string() + ": " + why);
  }
  void warn(const std::string& what) { model_.warnings.push_back(file_.string() + ": " + what); }

  // Base colour (glTF's baseColorFactor, else the diffuse colour: OBJ's Kd) as the diffuse
  // reflectance, less what metallic sends to the specular lobe; emissive colour times its
  // strength (KHR_materials_emissive_strength) as radiance, so emission (radiosity) is pi
  // times it, as Cycles reads the same file; the normal map as the material's bump.
  // Assimp's glTF importer keeps the file's materials in order (its default one last).
  void read_material(const aiMaterial& m, unsigned index) {
    Material out;
    out.name = m.GetName().C_Str();
    if (out.name.empty()) out.name = "material " + std::to_string(model_.materials.size());
    const std::string what = "material \"" + out.name + "\"";
    aiColor4D base(0.8f, 0.8f, 0.8f, 1);
    if (m.Get(AI_MATKEY_BASE_COLOR, base) != AI_SUCCESS) m.Get(AI_MATKEY_COLOR_DIFFUSE, base);
    Rgb colour(base.r, base.g, base.b);
    if (!(glm::all(glm::greaterThanEqual(colour, Rgb(0)))))
      fail(what + ": its base colour is negative or not a number");
    // Metallic/roughness (glTF): metal reflects its base colour in a Phong lobe whose
    // exponent follows the roughness, n = 2 / r^4 - 2 (Blinn-Phong against Beckmann's
    // alpha = r^2), a mirror below r = 0.05, at least 1; the rest is diffuse. A dielectric's
    // 4 % specular coat is not modelled: metallic 0 is Lambert at any roughness.
    float metallic = 0, roughness = 1;
    m.Get(AI_MATKEY_METALLIC_FACTOR, metallic);
    m.Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness);
    if (!(metallic >= 0 && metallic <= 1) || !(roughness >= 0 && roughness <= 1))
      fail(what + ": metallic and roughness must be in [0, 1]");
    bool clamped = false;
    if (auto image = texture(m, {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}, what,
                             PixelMeaning::Color)) {
      // glTF: base colour = factor x texture (sRGB decoded), per texel.
      for (std::size_t i = 0; i < image->rgb.size(); ++i) {
        const float v = image->rgb[i] * float(colour[int(i % 3)]);
        clamped = clamped || v > float(kMaxReflectance);
        image->rgb[i] = std::min(v, float(kMaxReflectance));
      }
      colour = image_mean(*image);
      if (metallic > 0)
        for (float& v : image->rgb) v *= 1 - metallic;
      ColorTexture t;
      t.kind = ColorTexture::Kind::Image;
      t.image = std::move(image);
      out.texture = std::move(t);
      out.reflectance = texture_mean(*out.texture);
    } else {
      clamped = glm::any(glm::greaterThan(colour, Rgb(kMaxReflectance)));
      colour = glm::min(colour, Rgb(kMaxReflectance));
      out.reflectance = colour * double(1 - metallic);
    }
    material_warnings_.emplace_back();
    if (clamped)
      material_warnings_.back().push_back(what + ": base colour above 0.99 read as 0.99");
    if (metallic > 0) {
      out.specular = metallic * (colour.r + colour.g + colour.b) / 3;
      out.shininess =
          roughness < 0.05 ? 0 : std::clamp(2 / std::pow(double(roughness), 4) - 2, 1.0, 1e6);
    }

    aiColor3D emissive(0, 0, 0);
    float strength = 1;
    m.Get(AI_MATKEY_COLOR_EMISSIVE, emissive);
    m.Get(AI_MATKEY_EMISSIVE_INTENSITY, strength);
    if (gltf_) strength = float(gltf_emissive_strength(*gltf_, index).value_or(strength));
    Rgb radiance = double(strength) * Rgb(emissive.r, emissive.g, emissive.b);
    if (auto image = texture(m, {aiTextureType_EMISSIVE, aiTextureType_EMISSION_COLOR}, what,
                             PixelMeaning::Color)) {
      // The surface emits the texture's mean evenly, so its power is the file's, and shows
      // the texture itself (scaled to mean 1: Material::emission_texture).
      const Rgb mean = image_mean(*image);
      radiance *= mean;
      for (std::size_t i = 0; i < image->rgb.size(); ++i) {
        const double c = mean[int(i % 3)];
        image->rgb[i] = c > 0 ? float(image->rgb[i] / c) : 0.0f;
      }
      ColorTexture t;
      t.kind = ColorTexture::Kind::Image;
      t.image = std::move(image);
      out.emission_texture = std::move(t);
      material_warnings_.back().push_back(
          what +
          ": its emissive texture is shown, but the light it sends is its mean, evenly over "
          "the surface");
    }
    // Every surface in bumprad is opaque: a cut-out (MASK) or see-through (BLEND) part
    // casts its whole shadow and shows its colour.
    aiString alpha_mode;
    if (m.Get(AI_MATKEY_GLTF_ALPHAMODE, alpha_mode) == AI_SUCCESS &&
        std::string_view(alpha_mode.C_Str()) != "OPAQUE")
      material_warnings_.back().push_back(what + ": its alphaMode " + alpha_mode.C_Str() +
                                          " is read as OPAQUE (bumprad's surfaces are opaque)");
    out.emission = std::numbers::pi * radiance;
    if (!(glm::all(glm::greaterThanEqual(out.emission, Rgb(0)))) ||
        !std::isfinite(out.emission.r + out.emission.g + out.emission.b))
      fail(what + ": its emission is negative or not a number");

    // glTF's normalTexture (with its scale), OBJ's norm; OBJ's bump/map_Bump is read as a
    // normal map too (with its -bm), as Blender reads it: exporters write normal maps there.
    int two_sided = 0;
    m.Get(AI_MATKEY_TWOSIDED, two_sided);
    material_two_sided_.push_back(two_sided != 0);
    material_bump_.push_back(-1);
    std::vector<aiTextureType> normals{aiTextureType_NORMALS};
    if (obj_) normals.push_back(aiTextureType_HEIGHT);
    for (aiTextureType type : normals)
      if (auto image = texture(m, {type}, what, PixelMeaning::Data)) {
        BumpFunction b;
        b.name = out.name + "/normal";
        b.type = BumpType::NormalMap;
        b.image = std::move(image);
        float scale = 1;
        if (m.Get(AI_MATKEY_GLTF_TEXTURE_SCALE(type, 0), scale) != AI_SUCCESS)
          m.Get(AI_MATKEY_OBJ_BUMPMULT(type, 0), scale);
        if (!(scale >= 0 && std::isfinite(scale)))
          fail(what + ": its normal map's scale must be a number >= 0");
        b.strength = scale;
        material_bump_.back() = int(model_.bumps.size());
        model_.bumps.push_back(std::move(b));
        break;
      }
    model_.materials.push_back(out);
  }

  // The material's first texture of these types, embedded in the file or beside it, decoded
  // within the image budget; none when there is none. `what` names the material in errors.
  std::shared_ptr<Image> texture(const aiMaterial& m, std::initializer_list<aiTextureType> types,
                                 const std::string& material, PixelMeaning meaning) {
    aiString path;
    const auto found = std::find_if(types.begin(), types.end(), [&](aiTextureType t) {
      return m.GetTexture(t, 0, &path) == AI_SUCCESS;
    });
    if (found == types.end()) return nullptr;
    std::string name = path.C_Str();
    const std::string what = material + ": texture \"" + name + "\"";
    // Models written on Windows name textures with backslashes (".\\wall.jpg").
    std::replace(name.begin(), name.end(), '\\', '/');
    try {
      if (const aiTexture* embedded = scene_.GetEmbeddedTexture(path.C_Str())) {
        if (embedded->mHeight != 0) fail(what + ": uncompressed embedded textures are not read");
        const std::string format = embedded->achFormatHint[0] ? embedded->achFormatHint : "png";
        return std::make_shared<Image>(decode_image(
            std::string_view(reinterpret_cast<const char*>(embedded->pcData), embedded->mWidth),
            "texture." + format, budget_, meaning));
      }
      const std::filesystem::path file = file_.parent_path() / name;
      if (confine_ && !lies_inside(*confine_, file))
        fail(what +
             " lies outside the files this model may read (the scene's \"files\", or the "
             "server's asset directory)");
      if (!std::filesystem::exists(file)) fail(what + " is missing");
      if (!std::filesystem::is_regular_file(file)) fail(what + " is not a regular file");
      return std::make_shared<Image>(read_image(file, budget_, meaning));
    } catch (const ModelError&) {
      throw;
    } catch (const std::exception& e) {
      // The decoder's message names the file or "texture.png"; say which texture it was.
      const std::string why = e.what();
      fail(what + ": " + why.substr(why.find(": ") == std::string::npos ? 0 : why.find(": ") + 2));
    }
  }

  void visit(const aiNode& node, const aiMatrix4x4& parent) {
    const aiMatrix4x4 to_world = parent * node.mTransformation;
    for (unsigned i = 0; i < node.mNumMeshes; ++i)
      add_mesh(node, *scene_.mMeshes[node.mMeshes[i]], to_world);
    for (unsigned i = 0; i < node.mNumChildren; ++i) visit(*node.mChildren[i], to_world);
  }

  void add_mesh(const aiNode& node, const aiMesh& mesh, const aiMatrix4x4& to_world) {
    if (!(mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) return;
    std::string name = node.mName.C_Str();
    if (mesh.mName.length > 0 && name != mesh.mName.C_Str())
      name += std::string("/") + mesh.mName.C_Str();
    TriangleMeshShape shape;
    shape.smooth = true;
    const aiMatrix3x3 linear(to_world);
    aiMatrix3x3 normal_matrix(to_world);
    normal_matrix.Inverse().Transpose();
    // A mirroring transform turns the triangles inside out: their winding flips back.
    const bool mirrored = aiMatrix3x3(to_world).Determinant() < 0;
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const Vec3 p = vec(to_world * mesh.mVertices[v]);
      if (!finite_within_limit(p))
        fail("mesh \"" + name + "\": vertex " + std::to_string(v) +
             " is not a finite point within 1e12");
      shape.positions.push_back(p);
      if (mesh.mNormals) {
        const Vec3 n = vec(normal_matrix * mesh.mNormals[v]);
        shape.normals.push_back(glm::length(n) > 0 ? glm::normalize(n) : n);
        // Assimp gives glTF's TANGENT as the tangent and its bitangent w (normal x tangent).
        if (mesh.mTangents && mesh.mBitangents)
          shape.tangents.push_back(with_handedness(shape.normals.back(),
                                                   vec(linear * mesh.mTangents[v]),
                                                   vec(linear * mesh.mBitangents[v])));
      }
      // Assimp gives v up the texture (OpenGL's convention); bumprad's images run down their
      // rows, as glTF's texture coordinates do.
      if (mesh.mTextureCoords[0])
        shape.uvs.push_back({mesh.mTextureCoords[0][v].x, 1 - double(mesh.mTextureCoords[0][v].y)});
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;
      std::array<std::uint32_t, 3> t{face.mIndices[0], face.mIndices[1], face.mIndices[2]};
      if (mirrored) std::swap(t[1], t[2]);
      if (degenerate_triangle(shape.positions[t[0]], shape.positions[t[1]],
                              shape.positions[t[2]])) {
        ++dropped_;
        continue;
      }
      shape.triangles.push_back(t);
    }
    if (shape.triangles.empty()) return;
    if (shape.uvs.empty()) {
      project_uvs(shape);
      without_uvs_.push_back(name);
    }
    const std::size_t material =
        std::min<std::size_t>(mesh.mMaterialIndex, model_.materials.size() - 1);
    if (material_two_sided_[material] && has_open_edges(shape)) add_back_faces(shape);
    Object o;
    o.name = name;
    o.material = int(material);
    o.bump = material_bump_[std::size_t(o.material)];
    o.shape = std::move(shape);
    model_.objects.push_back(std::move(o));
  }

  // Whether some edge (between two positions) belongs to one triangle only: an open sheet
  // (a leaf, a curtain, a plane) whose back can be seen. A closed mesh's cannot, from outside.
  static bool has_open_edges(const TriangleMeshShape& m) {
    auto key = [](const Vec3& p) { return std::array<double, 3>{p.x, p.y, p.z}; };
    std::map<std::pair<std::array<double, 3>, std::array<double, 3>>, int> uses;
    for (const auto& t : m.triangles)
      for (int e = 0; e < 3; ++e) {
        auto a = key(m.positions[t[std::size_t(e)]]), b = key(m.positions[t[(e + 1) % 3]]);
        if (b < a) std::swap(a, b);
        ++uses[{a, b}];
      }
    return std::any_of(uses.begin(), uses.end(), [](const auto& u) { return u.second == 1; });
  }

  // glTF's doubleSided on an open sheet: its back as a second sheet facing the other way,
  // a ten-thousandth of the mesh's extent behind, so each side receives and shows light (a
  // surface in bumprad is lit on its front only; coincident sheets would fight over hits).
  static void add_back_faces(TriangleMeshShape& m) {
    const auto [lo, hi] = bounds(m);
    const double offset = 1e-4 * glm::length(hi - lo);
    std::vector<Vec3> facing(m.positions.size(), Vec3(0));
    for (const auto& t : m.triangles) {
      const Vec3 n =
          glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
      for (std::uint32_t v : t) facing[v] += n;
    }
    const auto first = std::uint32_t(m.positions.size());
    for (std::size_t v = 0; v < facing.size(); ++v) {
      const Vec3 n = glm::length(facing[v]) > 0 ? glm::normalize(facing[v]) : Vec3(0);
      m.positions.push_back(m.positions[v] - offset * n);
      if (!m.normals.empty()) m.normals.push_back(-m.normals[v]);
      if (!m.uvs.empty()) m.uvs.push_back(m.uvs[v]);
      // The back's normal is the front's turned: the same tangent, the other handedness.
      if (!m.tangents.empty()) m.tangents.push_back({Vec3(m.tangents[v]), -m.tangents[v].w});
    }
    const std::size_t count = m.triangles.size();
    for (std::size_t i = 0; i < count; ++i) {
      const auto t = m.triangles[i];
      m.triangles.push_back({first + t[0], first + t[2], first + t[1]});
    }
  }

  // (u, v) for a mesh without them: each vertex projected along the main axis of its normal
  // onto the other two (x -> (z, y), y -> (x, z), z -> (x, y)), in units of the mesh's
  // largest extent. Continuous across every flat or gently curved run of triangles; a
  // triangle whose corners' normals lean to different axes is stretched between them.
  static void project_uvs(TriangleMeshShape& m) {
    const auto [lo, hi] = bounds(m);
    const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-300});
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      const Vec3 n = m.normals.empty() ? Vec3(0, 0, 1) : glm::abs(m.normals[i]);
      const Vec3 p = (m.positions[i] - lo) / extent;
      if (n.x >= n.y && n.x >= n.z)
        m.uvs.push_back({p.z, p.y});
      else if (n.y >= n.z)
        m.uvs.push_back({p.x, p.z});
      else
        m.uvs.push_back({p.x, p.y});
    }
  }

  // The node's transform to the world.
  aiMatrix4x4 world_of(const aiString& name) const {
    aiMatrix4x4 to_world;
    for (const aiNode* n = scene_.mRootNode->FindNode(name); n; n = n->mParent)
      to_world = n->mTransformation * to_world;
    return to_world;
  }

  // KHR_lights_punctual through Assimp (colour times intensity), placed by their nodes.
  // Candela (point, spot) and lux (sun) become W/sr and W/m^2 at 683 lm/W, the conversion
  // Blender's glTF importer makes, so Cycles renders the same file alike.
  void read_lights() {
    constexpr double kLumensPerWatt = 683;
    for (unsigned i = 0; i < scene_.mNumLights; ++i) {
      const aiLight& a = *scene_.mLights[i];
      PunctualLight l;
      l.name = a.mName.C_Str();
      if (a.mType == aiLightSource_POINT) {
        l.kind = PunctualLight::Kind::Point;
      } else if (a.mType == aiLightSource_SPOT) {
        l.kind = PunctualLight::Kind::Spot;
        l.inner_cone_deg = double(a.mAngleInnerCone) * 180 / std::numbers::pi;
        l.outer_cone_deg = double(a.mAngleOuterCone) * 180 / std::numbers::pi;
      } else if (a.mType == aiLightSource_DIRECTIONAL) {
        l.kind = PunctualLight::Kind::Directional;
      } else {
        warn("light \"" + l.name + "\": only point, spot and directional lights are read");
        continue;
      }
      const aiMatrix4x4 to_world = world_of(a.mName);
      l.position = vec(to_world * a.mPosition);
      const Vec3 d = vec(aiMatrix3x3(to_world) * a.mDirection);
      l.direction = glm::length(d) > 0 ? glm::normalize(d) : Vec3(0, 0, -1);
      l.intensity = Rgb(a.mColorDiffuse.r, a.mColorDiffuse.g, a.mColorDiffuse.b) / kLumensPerWatt;
      if (!finite_within_limit(l.position) ||
          !(glm::all(glm::greaterThanEqual(l.intensity, Rgb(0)))) ||
          !(l.kind != PunctualLight::Kind::Spot || l.outer_cone_deg > l.inner_cone_deg))
        fail("light \"" + l.name + "\" is not usable (position, intensity or cone)");
      model_.lights.push_back(l);
    }
  }

  // The first camera, placed by its node. Assimp's importers give the whole horizontal field
  // of view (whatever aiCamera's comment says); its glTF importer also copies the node's
  // translation into the camera's local position, which would apply it twice, and derives
  // the angle differently from one version to the next, so a glTF camera's yfov and aspect
  // ratio are read from the file's JSON and its position is its node's origin.
  void read_camera() {
    if (scene_.mNumCameras == 0) return;
    const aiCamera& cam = *scene_.mCameras[0];
    const aiMatrix4x4 to_world = world_of(cam.mName);
    const aiVector3D local = gltf_ ? aiVector3D(0, 0, 0) : cam.mPosition;
    Camera c;
    c.position = vec(to_world * local);
    c.look_at = vec(to_world * (local + cam.mLookAt));
    c.up = glm::normalize(vec(aiMatrix3x3(to_world) * cam.mUp));
    double aspect = cam.mAspect > 0 ? cam.mAspect : 1;
    if (cam.mHorizontalFOV > 0)
      c.fov_y_deg =
          2 * std::atan(std::tan(double(cam.mHorizontalFOV) / 2) / aspect) * 180 / std::numbers::pi;
    if (const auto p = gltf_ ? first_perspective_camera(*gltf_) : std::nullopt) {
      if (p->aspect > 0) aspect = p->aspect;
      c.fov_y_deg = p->yfov * 180 / std::numbers::pi;
    }
    c.width = 512;
    c.height = std::max(1, int(std::lround(512 / aspect)));
    if (!finite_within_limit(c.position) || !finite_within_limit(c.look_at) ||
        !(c.fov_y_deg > 0 && c.fov_y_deg < 180))
      fail("camera \"" + std::string(cam.mName.C_Str()) + "\" is not usable");
    model_.camera = c;
  }

  const std::filesystem::path& file_;
  const aiScene& scene_;
  const std::optional<std::filesystem::path>& confine_;
  ImageBudget own_budget_{Limits::kMaxTexturePixels, 0};  // when the caller gives none
  ImageBudget* budget_;
  const bool obj_;
  std::optional<nlohmann::json> gltf_;  // a glTF file's JSON, for what Assimp misreads
  ImportedModel model_;
  std::vector<int> material_bump_;        // per material: its normal map in model_.bumps, or -1
  std::vector<bool> material_two_sided_;  // per material: glTF's doubleSided
  std::size_t dropped_ = 0;
  std::vector<std::string> without_uvs_;  // meshes given projected texture coordinates
  std::vector<std::vector<std::string>> material_warnings_;  // per material read
};

}  // namespace

bool is_model_file(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  return !ext.empty() && ext != ".json" && Assimp::Importer().IsExtensionSupported(ext);
}

ImportedModel import_model(const std::filesystem::path& file,
                           const std::optional<std::filesystem::path>& confine,
                           ImageBudget* budget) {
  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene =
      importer.ReadFile(file.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                           aiProcess_SortByPType | aiProcess_GenNormals |
                                           aiProcess_ValidateDataStructure);
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw ModelError(file.string() + ": " +
                     (std::filesystem::exists(file) ? importer.GetErrorString() : "no such file"));
  return Reader(file, *scene, confine, budget).read();
}

void transform_model(ImportedModel& model, const glm::dmat4& to_world) {
  const glm::dmat3 linear(to_world);
  const glm::dmat3 normals = glm::transpose(glm::inverse(linear));
  const bool mirrored = glm::determinant(linear) < 0;
  auto point = [&](const Vec3& p) { return Vec3(to_world * glm::dvec4(p, 1)); };
  for (Object& o : model.objects) {
    auto& m = std::get<TriangleMeshShape>(o.shape);
    for (Vec3& p : m.positions) {
      p = point(p);
      if (!finite_within_limit(p))
        throw ModelError("object \"" + o.name + "\": the transform takes it beyond 1e12");
    }
    for (std::size_t v = 0; v < m.normals.size(); ++v) {
      const Vec3 n = m.normals[v];
      const Vec3 moved = glm::length(normals * n) > 0 ? glm::normalize(normals * n) : n;
      if (!m.tangents.empty()) {
        const Vec3 t(m.tangents[v]);
        m.tangents[v] =
            with_handedness(moved, linear * t, linear * (m.tangents[v].w * glm::cross(n, t)));
      }
      m.normals[v] = moved;
    }
    if (mirrored)
      for (auto& t : m.triangles) std::swap(t[1], t[2]);
  }
  for (PunctualLight& l : model.lights) {
    l.position = point(l.position);
    if (glm::length(linear * l.direction) > 0) l.direction = glm::normalize(linear * l.direction);
  }
  if (model.camera) {
    model.camera->position = point(model.camera->position);
    model.camera->look_at = point(model.camera->look_at);
    model.camera->up = glm::normalize(linear * model.camera->up);
  }
}

}  // namespace bumprad
