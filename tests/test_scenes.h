// Small scenes built in code for the tests: single quads, closed boxes.
#pragma once

#include <functional>
#include <vector>

#include "solver/scene/scene.h"
#include "solver/util/image.h"

namespace bumprad::test {

// A quad object meshed into nu x nv elements, one patch per element.
Object quad(const std::array<Vec3, 4>& corners, int nu = 1, int nv = 1, int material = 0);

// A 1 x 1 square in z = 0 facing up from `corner`, as an n x n grid of triangle pairs.
TriangleMeshShape square_of_triangles(const Vec3& corner, int n, bool smooth);

// Smooth hills facing up (+y): an n x n grid of triangle pairs over [0, side]^2 in x and z,
// the vertex at (u, v) in [0, 1]^2 raised to height(u, v).
TriangleMeshShape hills(int n, double side, const std::function<double(double, double)>& height);

// A smooth ball of radius r about `centre`, facing out: latitude-longitude rings of
// triangle pairs, 2 x rings around.
TriangleMeshShape ball(const Vec3& centre, double r, int rings);

// An axis-aligned w x h rectangle at height z facing down (-z), centred on the z axis.
std::array<Vec3, 4> rectangle_facing_down(double w, double h, double z);

// A glossy floor (k_d 0, k_s 1, Phong exponent 20) in z = 0 facing up, and a small emitter
// (0.2 x 0.2, E = 50) at z = 1 facing down in the floor's mirror direction as seen from the
// camera, which looks from (-1, 0, 1) at the origin with a 1-degree field of view: every
// pixel shows the highlight of a light much smaller than the lobe.
Scene glossy_highlight();
// The radiance the camera of glossy_highlight() sees at the origin: the integral of
// (E / pi) lobe.pdf(d) over the emitter, by a 64 x 64 midpoint rule on its area.
double glossy_highlight_radiance(const Scene& scene);
// The green channel's mean over an image's pixels, and their scatter (standard deviation
// over the mean): how quiet a highlight is.
struct PixelSpread {
  double mean, scatter;
};
PixelSpread pixel_spread(const Image& image);

// A scene with one grey material of reflectance `rho` and emission `emission`.
Scene scene_of(std::vector<Object> objects, double rho = 0.5, double emission = 0);

// A closed 4 x 4 x 4 m room of quads (8 x 8 elements each, seen from inside) and, object 0,
// a one-sided slab of 40 x 40 triangle pairs facing up across it at 1.4 m, where it cuts
// the walls' second row of elements (1 to 1.5 m) near its top: the pocket beneath is closed
// off. One material, as scene_of().
Scene slab_across_a_closed_room(double rho = 0.5, double emission = 0);

// A lamp's material: emits `emission`, reflects nothing.
Material emitter(double emission);

}  // namespace bumprad::test
