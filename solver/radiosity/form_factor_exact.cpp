#include "solver/radiosity/form_factor_exact.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <glm/geometric.hpp>

#include "solver/scene/geometry.h"

namespace bumprad {
namespace {

// atan(x) for x >= 0 (Moshier's Cephes: reduced to |x| <= 0.66 by atan(x) = pi/4 +
// atan((x - 1)/(x + 1)) or pi/2 - atan(1/x), then x + x^3 P(x^2)/Q(x^2)).
double atan_nonnegative(double x) {
  static constexpr std::array<double, 5> kP = {
      -8.750608600031904122785e-1, -1.615753718733365076637e1, -7.500855792314704667340e1,
      -1.228866684490136173410e2, -6.485021904942025371773e1};
  static constexpr std::array<double, 5> kQ = {2.485846490142306297962e1, 1.650270098316988542046e2,
                                               4.328810604912902668951e2, 4.853903996359136964868e2,
                                               1.945506571482613964425e2};
  constexpr double kMoreBits = 6.123233995736765886130e-17;  // pi/2 less its double
  double base = 0, extra = 0;
  if (x > 2.41421356237309504880) {  // tan(3 pi / 8)
    base = std::numbers::pi / 2;
    extra = kMoreBits;
    x = -1 / x;
  } else if (x > 0.66) {
    base = std::numbers::pi / 4;
    extra = 0.5 * kMoreBits;
    x = (x - 1) / (x + 1);
  }
  const double z = x * x;
  const double p = (((kP[0] * z + kP[1]) * z + kP[2]) * z + kP[3]) * z + kP[4];
  const double q = ((((z + kQ[0]) * z + kQ[1]) * z + kQ[2]) * z + kQ[3]) * z + kQ[4];
  return base + (x * z * p / q + x + extra);
}

// The polygon clipped to the half-space normal . (x - point) >= 0 (Sutherland-Hodgman), its
// corners relative to `point`, in `out`, which holds twice the polygon's corners.
inline std::span<const Vec3> clip_to_front(const Vec3& point, const Vec3& normal,
                                           std::span<const Vec3> polygon, std::span<Vec3> out) {
  std::size_t count = 0;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 a = polygon[i] - point, b = polygon[(i + 1) % n] - point;
    double da = glm::dot(normal, a), db = glm::dot(normal, b);
    if (da >= 0) out[count++] = a;
    if ((da >= 0) != (db >= 0)) out[count++] = a + (b - a) * (da / (da - db));
  }
  return out.first(count);
}

}  // namespace

double angle(double y, double x) {
  if (x > 0) return atan_nonnegative(y / x);
  if (x < 0) return std::numbers::pi - atan_nonnegative(y / -x);
  return y > 0 ? std::numbers::pi / 2 : 0;
}

double area_in_front(const Vec3& point, const Vec3& normal, std::span<const Vec3> polygon) {
  std::array<Vec3, 8> out;
  if (polygon.size() > 4) throw std::invalid_argument("area_in_front: more than 4 corners");
  const std::span<const Vec3> clipped = clip_to_front(point, normal, polygon, out);
  Vec3 twice(0);  // the vector area, twice
  for (std::size_t i = 0; i < clipped.size(); ++i)
    twice += glm::cross(clipped[i], clipped[(i + 1) % clipped.size()]);
  return 0.5 * glm::length(twice);
}

double point_to_polygon(const Vec3& point, const Vec3& normal, std::span<const Vec3> polygon) {
  // Small polygons clip on the stack: the view pass calls this per pixel.
  std::array<Vec3, 16> stack;
  std::vector<Vec3> heap;
  std::span<Vec3> out(stack);
  if (2 * polygon.size() > stack.size()) {
    heap.resize(2 * polygon.size());
    out = heap;
  }
  const std::span<const Vec3> clipped = clip_to_front(point, normal, polygon, out);
  double sum = 0;
  for (std::size_t i = 0; i < clipped.size(); ++i) {
    const Vec3& a = clipped[i];
    const Vec3& b = clipped[(i + 1) % clipped.size()];
    Vec3 c = glm::cross(a, b);
    double len = glm::length(c);
    if (len <= 0) continue;
    double gamma = angle(len, glm::dot(a, b));
    sum += gamma * glm::dot(normal, c) / len;
  }
  return std::abs(sum) / (2 * std::numbers::pi);
}

Vec3 polygon_vector(const Vec3& point, std::span<const Vec3> polygon) {
  // Lambert's sum before the normal's dot product: each edge's angle times the unit normal
  // of the plane through it and the point.
  Vec3 sum(0);
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec3 a = polygon[i] - point, b = polygon[(i + 1) % polygon.size()] - point;
    const Vec3 c = glm::cross(a, b);
    const double len = glm::length(c);
    if (len > 0) sum += c * (angle(len, glm::dot(a, b)) / len);
  }
  // The winding gives the sign: the vector points to the polygon's side of the point, as
  // every direction to the polygon does (taken across the polygon's plane).
  const Vec3 plane = glm::cross(polygon[1] - polygon[0], polygon[2] - polygon[0]);
  if ((glm::dot(sum, plane) < 0) != (glm::dot(polygon[0] - point, plane) < 0)) sum = -sum;
  return sum / (2 * std::numbers::pi);
}

double point_to_element(const Mesh& mesh, const Element& e, double radius, const Vec3& point,
                        const Vec3& normal) {
  const Vec3 d = e.centroid - point;
  const double r2 = glm::dot(d, d);
  if (!(r2 > kSmallPatchRadii * kSmallPatchRadii * radius * radius)) {
    if (glm::dot(d, e.normal) >= 0) return 0;
    std::array<Vec3, 4> storage;
    return point_to_polygon(point, normal, element_corners(mesh, e, storage));
  }
  return small_patch(e.area * e.normal, d, normal);
}

double element_radius(const Mesh& mesh, const Element& e) {
  double radius = 0;
  for (int k = 0; k < e.vertex_count; ++k)
    radius = std::max(
        radius, double(glm::length(mesh.vertices[e.v[std::size_t(k)]].position - e.centroid)));
  return radius;
}

double parallel_rectangles(double a, double b, double c) {
  double x = a / c, y = b / c;
  double x1 = std::sqrt(1 + x * x), y1 = std::sqrt(1 + y * y);
  double f = std::log(x1 * x1 * y1 * y1 / (1 + x * x + y * y)) / 2 + x * y1 * std::atan(x / y1) +
             y * x1 * std::atan(y / x1) - x * std::atan(x) - y * std::atan(y);
  return 2 * f / (std::numbers::pi * x * y);
}

double perpendicular_rectangles(double l, double w, double h) {
  double W = w / l, H = h / l;
  double w2 = W * W, h2 = H * H, s = std::sqrt(w2 + h2);
  double log_term = std::log((1 + w2) * (1 + h2) / (1 + w2 + h2)) +
                    w2 * std::log(w2 * (1 + w2 + h2) / ((1 + w2) * (w2 + h2))) +
                    h2 * std::log(h2 * (1 + h2 + w2) / ((1 + h2) * (h2 + w2)));
  double f = W * std::atan(1 / W) + H * std::atan(1 / H) - s * std::atan(1 / s) + log_term / 4;
  return f / (std::numbers::pi * W);
}

}  // namespace bumprad
