#define GL_GLEXT_PROTOTYPES
#include "solver/radiosity/hemicube.h"
#include "common/stopwatch.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

namespace bumprad {
namespace {

// One face of the hemi-cube in the local frame. A pixel's direction is
// forward + ex * right + ey * up with right = forward x up, ex in [-1, 1] and ey in
// [ey_min, 1]: the side faces keep only their upper half, above the tangent plane.
struct Face {
  Vec3 forward, up;
  double ey_min;
};
constexpr int kFaces = 5;
// A group's proxy stands for it where the proxy's error is under this share of a pixel.
constexpr double kProxyPixels = 0.25;
const Face kFaceTable[kFaces] = {
    {{0, 0, 1}, {0, 1, 0}, -1},  //
    {{1, 0, 0}, {0, 0, 1}, 0},   //
    {{-1, 0, 0}, {0, 0, 1}, 0},  //
    {{0, 1, 0}, {0, 0, 1}, 0},   //
    {{0, -1, 0}, {0, 0, 1}, 0},
};
int face_row0(int face, int r) {
  return face == 0 ? 0 : r + (face - 1) * (r / 2);
}
int face_rows(int face, int r) {
  return face == 0 ? r : r / 2;
}

}  // namespace

DeltaFormFactors::DeltaFormFactors(int resolution) : resolution_(resolution) {
  if (resolution < 2 || resolution % 2)
    throw std::invalid_argument("hemi-cube resolution must be even and at least 2");
  const int r = resolution;
  const std::size_t n = std::size_t(r) * std::size_t(3 * r);
  df_.resize(n);
  weight_.resize(n);
  direction_.resize(n);
  const double da = (2.0 / r) * (2.0 / r);
  double total = 0;
  std::vector<double> weights(n);
  for (int f = 0; f < kFaces; ++f) {
    const Face& face = kFaceTable[f];
    Vec3 right = glm::cross(face.forward, face.up);
    int rows = face_rows(f, r);
    for (int row = 0; row < rows; ++row) {
      double ey = face.ey_min + (1 - face.ey_min) * (row + 0.5) / rows;
      for (int col = 0; col < r; ++col) {
        double ex = 2 * (col + 0.5) / r - 1;
        Vec3 d = face.forward + ex * right + ey * face.up;
        double r2 = glm::dot(d, d);
        double w = da / (std::numbers::pi * r2 * r2);
        std::size_t p = std::size_t(face_row0(f, r) + row) * std::size_t(r) + std::size_t(col);
        direction_[p] = glm::vec3(d);
        weights[p] = w;
        total += d.z * w;
      }
    }
  }
  // The exact integral is 1; normalising removes the discretisation's small excess.
  for (std::size_t p = 0; p < n; ++p) {
    weight_[p] = float(weights[p] / total);
    df_[p] = float(direction_[p].z * weights[p] / total);
  }
  mirror_.resize(n);
  for (std::size_t p = 0; p < n; ++p) {
    Vec3 d(direction_[p]);
    mirror_[p] = std::uint32_t(pixel_for(Vec3(-d.x, -d.y, d.z)));
  }
}

std::size_t DeltaFormFactors::pixel_for(const Vec3& d) const {
  if (!(d.z > 0)) return size();
  // The face whose forward axis the direction leans on most (the top face wins ties).
  int best = 0;
  double lean = d.z;
  for (int f = 1; f < kFaces; ++f) {
    double t = glm::dot(d, kFaceTable[f].forward);
    if (t > lean) best = f, lean = t;
  }
  const Face& face = kFaceTable[best];
  const int r = resolution_, rows = face_rows(best, r);
  double ex = glm::dot(d, glm::cross(face.forward, face.up)) / lean;
  double ey = glm::dot(d, face.up) / lean;
  int col = std::clamp(int((ex + 1) / 2 * r), 0, r - 1);
  int row = std::clamp(int((ey - face.ey_min) / (1 - face.ey_min) * rows), 0, rows - 1);
  return std::size_t(face_row0(best, r) + row) * std::size_t(r) + std::size_t(col);
}

Hemicube::Hemicube(const Mesh& mesh, int resolution)
    : mesh_(mesh),
      deltas_(resolution),
      context_(deltas_.width(), deltas_.height()),
      sums_(mesh.elements.size(), 0.0) {
  // Unshared corners so each element carries its own id colour; RGBA8 holds id + 1 exactly.
  corners_.reserve(mesh.elements.size() * 4);
  for (const Element& el : mesh.elements)
    for (int i = 0; i < 4; ++i)
      corners_.push_back(glm::vec3(mesh.vertices[el.v[std::min(i, el.vertex_count - 1)]].position));
  glGenBuffers(1, &vertex_buffer_);
  glGenBuffers(1, &color_buffer_);
  upload(element_ids());
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);
  glDisable(GL_DITHER);
  glDisable(GL_LIGHTING);
  glDisable(GL_CULL_FACE);  // culled on the CPU, per face, before drawing
  glShadeModel(GL_FLAT);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_SCISSOR_TEST);
  glClearColor(0, 0, 0, 0);
}

std::vector<std::uint32_t> Hemicube::element_ids() const {
  std::vector<std::uint32_t> ids(4 * mesh_.elements.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = std::uint32_t(i / 4 + 1);
  return ids;
}

void Hemicube::upload(std::span<const std::uint32_t> ids) {
  context_.make_current();
  glBindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(corners_.size() * sizeof(glm::vec3)), corners_.data(),
               GL_STATIC_DRAW);
  glVertexPointer(3, GL_FLOAT, 0, nullptr);
  glBindBuffer(GL_ARRAY_BUFFER, color_buffer_);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(ids.size() * sizeof(std::uint32_t)), ids.data(),
               GL_STATIC_DRAW);
  glColorPointer(4, GL_UNSIGNED_BYTE, 0, nullptr);
}

void Hemicube::use_proxies(GroupProxies proxies) {
  proxies_ = std::move(proxies);
  corners_.resize(mesh_.elements.size() * 4);
  std::vector<std::uint32_t> ids = element_ids();
  level_base_.clear();
  for (const ProxyLevel& level : proxies_.levels)
    for (const auto* list : {&level.triangles, &level.skirts}) {
      level_base_.push_back(std::uint32_t(corners_.size()));
      for (const ProxyTriangle& t : *list)
        for (int i = 0; i < 4; ++i) {
          corners_.push_back(t.corners[std::size_t(std::min(i, 2))]);
          ids.push_back(t.element + 1);
        }
    }
  upload(ids);
}

void Hemicube::watch(std::vector<bool> elements) {
  watched_ = std::move(elements);
  whole_.assign(mesh_.groups.size(), false);
  for (std::size_t e = 0; e < watched_.size(); ++e)
    if (watched_[e] && mesh_.elements[e].group < whole_.size())  // a mesh made without groups
      whole_[mesh_.elements[e].group] = true;
}

void Hemicube::render(const Vec3& origin, const Frame& frame,
                      std::optional<std::uint32_t> skip_patch) {
  auto t0 = Clock::now();
  context_.make_current();
  const int r = deltas_.resolution();
  glViewport(0, 0, context_.width(), context_.height());
  glScissor(0, 0, context_.width(), context_.height());
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  // Depth range: far past the farthest corner; near at a thousandth of the scene, small
  // against any element yet large enough for llvmpipe's 24-bit depth buffer to part
  // surfaces 1 mm apart across the scene (depth resolution ~ z^2 / near * 2^-24: 0.08 mm at
  // 3 m in a 6.5 m scene; at 1e-5 it was 8 mm, and a rug lying 1 mm above a floor vanished).
  double far = 0;
  for (int i = 0; i < 8; ++i) {
    Vec3 c((i & 1) ? mesh_.bounds_max.x : mesh_.bounds_min.x,
           (i & 2) ? mesh_.bounds_max.y : mesh_.bounds_min.y,
           (i & 4) ? mesh_.bounds_max.z : mesh_.bounds_min.z);
    far = std::max(far, glm::length(c - origin));
  }
  double near = std::max(mesh_.diagonal(), far) * 1e-3;
  far = far * 1.01 + near;

  // CPU culling: an element is drawn on a face only if it faces the origin and is not
  // wholly outside one of the face's four frustum planes (all through the origin).
  const glm::vec3 o(origin);
  std::array<Vec3, kFaces> forward;
  std::array<std::array<glm::vec3, 4>, kFaces> planes;
  for (int f = 0; f < kFaces; ++f) {
    const Face& face = kFaceTable[f];
    Vec3 fw = frame.to_world(face.forward), up = frame.to_world(face.up);
    Vec3 right = glm::cross(fw, up);
    forward[f] = fw;
    planes[f] = {glm::vec3(fw - right), glm::vec3(fw + right), glm::vec3(fw - up),
                 glm::vec3(face.ey_min < 0 ? fw + up : up)};
  }
  auto& face_indices = face_indices_;
  for (auto& v : face_indices) v.clear();
  // `corners` (4, a triangle's last repeated) at `base` in the buffers.
  auto draw = [&](std::uint32_t base, const Vec3& normal, const Vec3& centroid, bool quad) {
    if (glm::dot(normal, origin - centroid) <= 0) return;
    const glm::vec3* c = &corners_[base];
    const glm::vec3 rel[4] = {c[0] - o, c[1] - o, c[2] - o, c[3] - o};
    auto outside = [&](const glm::vec3& n) {
      return glm::dot(rel[0], n) < 0 && glm::dot(rel[1], n) < 0 && glm::dot(rel[2], n) < 0 &&
             glm::dot(rel[3], n) < 0;
    };
    for (int f = 0; f < kFaces; ++f) {
      const auto& p = planes[f];
      if (outside(p[0]) || outside(p[1]) || outside(p[2]) || outside(p[3])) continue;
      auto& idx = face_indices[f];
      idx.insert(idx.end(), {base, base + 1, base + 2});
      if (quad) idx.insert(idx.end(), {base, base + 2, base + 3});
    }
  };
  // A group far enough off for a proxy's error to stay under kProxyPixels of a pixel (2 / r
  // wide at the top face's centre, the widest) is drawn by the coarsest such proxy, with
  // its skirts where a neighbour is drawn another way.
  level_.assign(proxies_.spheres.size(), -1);
  const int levels = int(proxies_.levels.size());
  for (std::size_t g = 0; g < level_.size(); ++g) {
    if ((!whole_.empty() && whole_[g]) ||
        (skip_patch && mesh_.elements[mesh_.groups[g].first].patch == *skip_patch))
      continue;
    const GroupProxies::Sphere& sphere = proxies_.spheres[g];
    const double reach =
        kProxyPixels * 2.0 / r * (glm::length(sphere.centre - origin) - sphere.radius);
    for (int l = levels - 1; l >= 0 && level_[g] < 0; --l) {
      const ProxyLevel::Group& proxy = proxies_.levels[std::size_t(l)].groups[g];
      if (proxy.count > 0 && proxy.error <= reach) level_[g] = std::int8_t(l);
    }
  }
  for (std::size_t g = 0; g < level_.size(); ++g) {
    if (level_[g] < 0) continue;
    const std::size_t l = std::size_t(level_[g]);
    const ProxyLevel& level = proxies_.levels[l];
    const ProxyLevel::Group& proxy = level.groups[g];
    for (std::uint32_t t = proxy.first; t < proxy.first + proxy.count; ++t)
      draw(level_base_[2 * l] + 4 * t, Vec3(level.triangles[t].normal),
           Vec3(level.triangles[t].centroid), false);
    for (std::uint32_t t = proxy.skirt_first; t < proxy.skirt_first + proxy.skirt_count; ++t)
      if (level_[level.skirt_neighbour[t]] != level_[g])
        draw(level_base_[2 * l + 1] + 4 * t, Vec3(level.skirts[t].normal),
             Vec3(level.skirts[t].centroid), false);
  }
  for (std::size_t e = 0; e < mesh_.elements.size(); ++e) {
    const Element& el = mesh_.elements[e];
    if (!level_.empty() && level_[el.group] >= 0) {  // its group's elements lie together
      e = mesh_.groups[el.group].first + mesh_.groups[el.group].count - 1;
      continue;
    }
    if (skip_patch && el.patch == *skip_patch) continue;
    draw(std::uint32_t(4 * e), el.normal, el.centroid, el.vertex_count == 4);
  }

  for (int f = 0; f < kFaces; ++f) {
    if (face_indices[f].empty()) continue;
    const Face& face = kFaceTable[f];
    int row0 = face_row0(f, r), rows = face_rows(f, r);
    glViewport(0, row0, r, rows);
    glScissor(0, row0, r, rows);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glFrustum(-near, near, face.ey_min * near, near, near, far);
    glMatrixMode(GL_MODELVIEW);
    glm::dmat4 view = glm::lookAt(origin, origin + forward[f], frame.to_world(face.up));
    glLoadMatrixd(glm::value_ptr(view));
    glDrawElements(GL_TRIANGLES, GLsizei(face_indices[f].size()), GL_UNSIGNED_INT,
                   face_indices[f].data());
  }
  glFinish();
  render_seconds_ += seconds_since(t0);
}

std::span<const std::uint32_t> Hemicube::item_buffer() const {
  return {context_.pixels(), deltas_.size()};
}

std::vector<VisibleElement>& Hemicube::form_factors() {
  return accumulate([&](std::size_t p) { return double(deltas_.dF(p)); }, !watched_.empty());
}

std::vector<VisibleElement>& Hemicube::form_factors(std::span<const Vec3> lobes) {
  std::vector<glm::vec3> local(lobes.begin(), lobes.end());
  return accumulate(
      [&](std::size_t p) {
        const glm::vec3 d = deltas_.directional(p);
        float f = 0;
        for (const glm::vec3& lobe : local) f += std::max(0.0f, glm::dot(lobe, d));
        return double(f);
      },
      false);
}

template <typename Weight>
std::vector<VisibleElement>& Hemicube::accumulate(Weight weight, bool watching) {
  auto t0 = Clock::now();
  visible_.clear();
  watched_pixels_.clear();
  const std::uint32_t* ids = context_.pixels();
  for (std::size_t p = 0, n = deltas_.size(); p < n; ++p) {
    std::uint32_t id = ids[p];
    if (!id) continue;
    const double w = weight(p);
    if (!(w > 0)) continue;
    double& s = sums_[id - 1];
    if (s == 0) visible_.push_back({id - 1, 0});
    s += w;
    if (watching && watched_[id - 1]) watched_pixels_.push_back(std::uint32_t(p));
  }
  for (VisibleElement& v : visible_) {
    v.form_factor = sums_[v.element];
    sums_[v.element] = 0;
  }
  accumulate_seconds_ += seconds_since(t0);
  return visible_;
}

}  // namespace bumprad
