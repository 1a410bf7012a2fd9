// Surfaces the camera sees from behind. bumprad's surfaces are one-sided, so a model whose
// triangles wind the wrong way (or a box meant to be seen from inside) renders black there;
// this finds them, by object, so the user hears which and how much of the image they take.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"
#include "solver/scene/scene.h"

namespace bumprad {

struct BackFacing {
  std::uint32_t object;
  double share;  // of the image's pixels that show this object's back faces
};

// Objects of which the camera sees more back than front and whose backs fill at least 1 %
// of the image, from one ray through each cell of a grid of at most 64 x 64 over the image.
std::vector<BackFacing> back_facing_objects(const Scene& scene, const Mesh& mesh,
                                            const RayScene& rays);

// The warnings to show for them, one line each, naming the object and its share.
std::vector<std::string> back_face_warnings(const Scene& scene, const Mesh& mesh,
                                            const RayScene& rays);

}  // namespace bumprad
