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
  std::vector<std::uint32_t> colors;
  corners_.reserve(mesh.elements.size() * 4);
  colors.reserve(mesh.elements.size() * 4);
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
    const Element& el = mesh.elements[e];
    for (int i = 0; i < 4; ++i) {
      corners_.push_back(glm::vec3(mesh.vertices[el.v[std::min(i, el.vertex_count - 1)]].position));
      colors.push_back(std::uint32_t(e + 1));
    }
  }
  glGenBuffers(1, &vertex_buffer_);
  glBindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(corners_.size() * sizeof(glm::vec3)), corners_.data(),
               GL_STATIC_DRAW);
  glVertexPointer(3, GL_FLOAT, 0, nullptr);
  glGenBuffers(1, &color_buffer_);
  glBindBuffer(GL_ARRAY_BUFFER, color_buffer_);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(colors.size() * sizeof(std::uint32_t)), colors.data(),
               GL_STATIC_DRAW);
  glColorPointer(4, GL_UNSIGNED_BYTE, 0, nullptr);
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
  for (std::size_t e = 0; e < mesh_.elements.size(); ++e) {
    const Element& el = mesh_.elements[e];
    if (skip_patch && el.patch == *skip_patch) continue;
    if (glm::dot(el.normal, origin - el.centroid) <= 0) continue;
    const glm::vec3* c = &corners_[4 * e];
    const glm::vec3 rel[4] = {c[0] - o, c[1] - o, c[2] - o, c[3] - o};
    auto outside = [&](const glm::vec3& n) {
      return glm::dot(rel[0], n) < 0 && glm::dot(rel[1], n) < 0 && glm::dot(rel[2], n) < 0 &&
             glm::dot(rel[3], n) < 0;
    };
    std::uint32_t base = std::uint32_t(4 * e);
    for (int f = 0; f < kFaces; ++f) {
      const auto& p = planes[f];
      if (outside(p[0]) || outside(p[1]) || outside(p[2]) || outside(p[3])) continue;
      auto& idx = face_indices[f];
      idx.insert(idx.end(), {base, base + 1, base + 2});
      if (el.vertex_count == 4) idx.insert(idx.end(), {base, base + 2, base + 3});
    }
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
