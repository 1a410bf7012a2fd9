// The scene as the solver sees it: camera, materials, shapes and solver settings as plain
// values. protocol/ builds one from JSON and validates it; the solver trusts what it gets.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <glm/vec4.hpp>

#include "solver/util/image.h"
#include "solver/util/math.h"

namespace bumprad {

// Documented limits; protocol/ rejects scenes beyond them before any work is done.
struct Limits {
  static constexpr int kMaxElements = 2'000'000;
  static constexpr int kMinHemicube = 16;
  static constexpr int kMaxHemicube = 1024;
  static constexpr int kMaxImageSide = 8192;
  // An image a scene reads (texture, height or normal map), checked from its file's header
  // before it is decoded: 8192^2, 805 MB as linear floats.
  static constexpr std::size_t kMaxTexturePixels = std::size_t(kMaxImageSide) * kMaxImageSide;
  // What all the images of one scene (or one re-texture's new ones) may take to decode, by
  // default (ImageBudget): two 8-bit images at the pixel limit fit, three do not. A server
  // sets its own (--max-image-memory).
  static constexpr std::size_t kMaxImageBytes = std::size_t(2) << 30;
  static constexpr int kMaxShots = 1'000'000;
  static constexpr int kMaxGridCount = 4096;  // elements along one side of one surface
  static constexpr int kMaxAntialias = 8;
  static constexpr int kMaxAntialiasMax = 16;  // the adaptive grid (camera.h)
  // Coordinates and sizes, in scene units: squares and cross products must not overflow.
  static constexpr double kMaxMagnitude = 1e12;
};

struct Camera {
  Vec3 position{0, 0, -1};
  Vec3 look_at{0, 0, 0};
  Vec3 up{0, 1, 0};
  double fov_y_deg = 40;
  int width = 512;
  int height = 512;
  double exposure = 1;  // multiplies radiance before tone mapping
  // n: an n x n stratified grid of rays per pixel. 2 (with 4 x 4 where they disagree) by
  // default: at one ray a pixel no pixel is sampled again, and every edge is stepped.
  int antialias = 2;
  int antialias_max = 0;   // m: pixels whose n x n rays disagree get m x m; 0: 2n (camera.h)
  int max_depth = 5;       // specular bounces followed from the eye
  int glossy_samples = 8;  // lobe samples at the first glossy surface a ray meets
  int shadow_rays = 4;     // per ray hit, toward the emitters (DirectLight::Exact)
};

// How an image or pattern repeats outside [0,1]^2.
enum class Wrap { Repeat, Clamp, Mirror };

// A colour texture over a surface's (u,v): its colours are diffuse reflectances. The solve
// uses their mean (Material::reflectance); rendering scales the reflected radiosity by
// rho(u,v) / mean (Cohen et al. 1986), which is how the paper shows its chessboard floor.
struct ColorTexture {
  enum class Kind { Checker, Image };
  Kind kind = Kind::Checker;
  std::array<Rgb, 2> colors{Rgb(0.1), Rgb(0.8)};  // checker
  std::shared_ptr<const Image> image;             // image: linear reflectances
  Wrap wrap = Wrap::Repeat;
  glm::dvec2 scale{1, 1};  // checker: squares across the surface; image: repeats
  glm::dvec2 offset{0, 0};
};

// Diffuse albedo rho and emitted radiosity E (W/m^2, i.e. pi times the radiance).
// `specular` (k_s) and `shininess` (Phong's exponent) make a surface non-diffuse: the solve
// reflects k_s of the light it receives along the lobe (the paper's first pass, eq. 4-6) and
// the view pass traces its reflections (the second).
struct Material {
  std::string name;
  Rgb reflectance{0.5, 0.5, 0.5};
  Rgb emission{0, 0, 0};
  double specular = 0;
  double shininess = 0;  // 0 means a perfect mirror
  std::optional<ColorTexture> texture;
  // What the camera sees of the emission: E times this texture's colour at (u,v), whose mean
  // is 1 (a model's emissive texture). The light the surface sends is E, evenly.
  std::optional<ColorTexture> emission_texture;
};

// How finely one object is meshed. A count of 0 means "derive from element_size"; an
// element_size of 0 means "use the scene default".
struct MeshDensity {
  double element_size = 0;
  std::array<int, 2> counts{0, 0};
  int patch_elements = 0;  // elements per patch side; 0 means the scene default
};

struct QuadShape {
  std::array<Vec3, 4> corners;  // counter-clockwise seen from the lit side
};
struct BoxShape {
  Vec3 center{0, 0, 0};
  Vec3 size{1, 1, 1};
  Vec3 rotation_deg{0, 0, 0};  // applied about x, then y, then z
};
struct SphereShape {
  Vec3 center{0, 0, 0};
  double radius = 1;
};
struct CylinderShape {
  Vec3 base{0, 0, 0};
  Vec3 top{0, 1, 0};
  double radius = 1;
  bool caps = true;
};
struct TriangleMeshShape {
  std::vector<Vec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  bool smooth = false;  // share vertices (and interpolate radiosity) across triangles
  // Per position, or empty. With `uvs` a bump function or texture is evaluated at the
  // mesh's own (u, v), continuous across triangles; without, each triangle has its own
  // (u, v) in [0,1]^2. With `normals` (a model's shading normals), a smooth mesh shares a
  // vertex between triangles only where position, normal and (u, v) all agree: creases and
  // UV seams stay apart.
  std::vector<glm::dvec2> uvs;
  std::vector<Vec3> normals;
  // Per position, or empty: a model's own tangents (glTF's TANGENT), xyz along increasing u
  // and w = +-1 its handedness: w (normal x xyz) points up the texture. They set the bump
  // and normal-map frame's directions; without them it follows the (u, v), averaged over a
  // smooth mesh's triangles at each vertex as MikkTSpace does.
  std::vector<glm::dvec4> tangents;
};
using Shape = std::variant<QuadShape, BoxShape, SphereShape, CylinderShape, TriangleMeshShape>;

// A named bump (height) function; solver/scene/bump.h evaluates it.
enum class BumpType { Noise, Wrinkles, Bricks, Tiles, Dimples, Cylinder, Image, NormalMap };

// Heights are in scene units; the pattern is evaluated at uv * scale + offset, where uv is
// the surface's own parameterisation in [0,1]^2. A normal map gives the perturbed normal
// itself, in the surface's tangent frame, instead of heights.
struct BumpFunction {
  std::string name;
  BumpType type = BumpType::Wrinkles;
  double amplitude = 0.01;
  glm::dvec2 scale{1, 1};
  glm::dvec2 offset{0, 0};
  int octaves = 4;           // noise
  std::uint32_t seed = 1;    // noise
  double direction_deg = 0;  // wrinkles, cylinder: the (u,v) direction the height varies along
  double mortar = 0.08;      // bricks, tiles: groove width, fraction of a cell
  double radius = 0.35;      // dimples: fraction of a cell
  // image: grey-scale heights in [0,1]; normal map: tangent-space normals, (x, y, z) stored
  // as (x + 1) / 2 in red, green, blue, +x along u, +y toward the image's top row (OpenGL's
  // and glTF's convention), +z along the surface normal. Bilinear either way.
  std::shared_ptr<const Image> image;
  Wrap wrap = Wrap::Repeat;  // image, normal map
  double strength = 1;       // normal map: its x and y scaled by this (glTF's normalTexture.scale)
};

// A light with no area (glTF's KHR_lights_punctual): a point radiating `intensity` (W/sr) in
// every direction, a spot doing so within a cone about `direction` (full inside
// inner_cone_deg, falling to none at outer_cone_deg, as glTF defines it), or a directional
// light (the sun) whose parallel rays travel along `direction` with `intensity` read as the
// irradiance (W/m^2) of a surface facing them. No camera ray ever meets one.
struct PunctualLight {
  enum class Kind { Point, Spot, Directional };
  std::string name;
  Kind kind = Kind::Point;
  Vec3 position{0};
  Vec3 direction{0, -1, 0};  // spot and directional; unit length
  Rgb intensity{0};
  double inner_cone_deg = 0, outer_cone_deg = 45;  // spot
};

struct Object {
  std::string name;
  Shape shape;
  int material = 0;           // index into Scene::materials
  bool flip_normals = false;  // e.g. a box seen from inside
  MeshDensity density;
  int bump = -1;  // index into Scene::bumps, or -1 for a smooth surface
};

// Where the perturbed radiosity map comes from: none, a gather pass after the solve, or
// shooting at every refinement step (so every preview shows bumps).
enum class TextureMode { None, Gather, Shoot };

// How a shot's form factors are found: the hemi-cube's item buffer (Cohen & Greenberg 1985)
// or rays from each receiver to points on the shooter (Wallace, Elmquist & Haines 1989).
enum class FormFactorMethod { Hemicube, RayCast };

// Where an image's direct light comes from. Exact: per pixel, from the emitters (Lambert's
// closed form times the share shadow rays see, with the perturbed normal N'), while the
// radiosity solution and the perturbed map carry only the indirect light. Radiosity: all
// light from the solution and the map, as Chen & Wu render it.
enum class DirectLight { Exact, Radiosity };

// What the perturbed map stores per vertex (solver/radiosity/map_basis.h): spherical harmonics of
// the incident light, bands 0-2 and 4 (18 numbers a channel), or the paper's sampled normals.
enum class MapBasisKind { SphericalHarmonics, SampledNormals };

struct MapSettings {
  MapBasisKind basis = MapBasisKind::SphericalHarmonics;
  // Sampled normals only: N plus `azimuths` directions on each tilt ring.
  std::vector<double> tilts_deg{22.5, 45};
  int azimuths = 8;
  bool self_illumination = false;  // paper section 3: bumps lit by the surface itself
};

struct SolverSettings {
  int hemicube_resolution = 150;  // pixels across the top face; even
  int max_shots = 1000;
  // Stop once unshot power (in magnitude: overshooting leaves negative residuals) / emitted
  // power falls below this.
  double unshot_fraction = 0.01;
  // Target relative RMS error of the image against ground truth; 0: off. When set, the solve
  // estimates its error (solver/render/error_estimate.h) once it reaches unshot_fraction, and
  // while the estimate is above the target: shoots on to a third of the unshot power while
  // that lowers it by a tenth and max_shots allows; then renders with kToleranceAntialias
  // rays a pixel across; then splits elements as adaptive subdivision does, up to
  // kToleranceLevels levels beyond adaptive_levels, while each lowers it by a tenth.
  // SolveStats reports the estimate.
  double tolerance = 0;
  static constexpr int kToleranceAntialias = 4;
  static constexpr int kToleranceLevels = 2;
  double element_size = 0;      // 0: a sixteenth of the scene's bounding-box diagonal
  int patch_elements = 0;       // elements per patch side (patches shoot, elements receive);
                                // 0: automatic, mesh.h's patch_elements()
  int preview_every = 10;       // shots per refinement step (callback, preview)
  bool rotate_hemicube = true;  // random rotation about N per shot against aliasing
  FormFactorMethod form_factors = FormFactorMethod::Hemicube;
  // Hemi-cube shots: receivers expected to cover fewer pixels than this get ray-cast form
  // factors instead (aliasing); 0 turns the fallback off.
  double alias_pixels = 1;
  // Adaptive subdivision (Cohen et al. 1986): after a solve, split elements whose radiosity
  // differs from a neighbour's by more than adaptive_threshold (relative), and solve again,
  // at most adaptive_levels times. 0 levels: the mesh stays as built.
  int adaptive_levels = 0;
  double adaptive_threshold = 0.1;
  std::uint32_t seed = 1;
  TextureMode texture = TextureMode::Shoot;
  DirectLight direct_light = DirectLight::Exact;
  MapSettings map;
};

struct Scene {
  Camera camera;
  std::vector<Material> materials;
  std::vector<Object> objects;
  std::vector<BumpFunction> bumps;
  std::vector<PunctualLight> lights;
  SolverSettings solver;
};

}  // namespace bumprad
