// A pinhole camera: image-plane positions to world-space rays.
#pragma once

#include "solver/scene/mesh.h"
#include "solver/scene/scene.h"

namespace bumprad {

struct Ray {
  Vec3 origin, direction;  // direction is unit length
};

// The camera of previews and interactive drafts: one ray per pixel, at most two glossy
// samples and one shadow ray. Full-quality previews of paper-room took 7 times as long as its
// solve.
Camera draft_camera(Camera camera);

// Whether two cameras take the same image before exposure (which only scales it): a view
// pass kept for one serves the other.
bool same_view(const Camera& a, const Camera& b);

// The grid m of adaptive antialiasing: pixels whose n x n samples disagree are sampled again
// on an m x m grid. camera.antialias_max, or 0 for 2n (at most Limits::kMaxAntialiasMax); at
// most n (and with n = 1, which gives no disagreement to see) turns it off.
int adaptive_antialias(const Camera& camera);

// `camera` (its image size and field of view kept) placed to see a scene that names none
// (a model file without a camera). An object, its faces turned out on the whole, is seen
// from in front (+z, glTF's front), its bounding sphere filling the view. A room (faces
// turned in: what lights it from inside) is seen across from the side of its bounds with the
// least wall facing in, sides before floor and ceiling: from outside an open side (the
// Cornell box's), from just inside a closed room's wall.
Camera framed_camera(const Mesh& mesh, Camera camera);

class PinholeCamera {
 public:
  explicit PinholeCamera(const Camera& camera);
  // (x, y) in pixels from the top-left corner of the image; (0.5, 0.5) is the first centre.
  Ray ray(double x, double y) const;

 private:
  Vec3 position_, forward_, right_, up_;
  double half_height_, half_width_;
  int width_, height_;
};

}  // namespace bumprad
