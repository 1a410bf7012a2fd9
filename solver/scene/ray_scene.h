// The mesh's elements in an Embree BVH, for the view pass's rays and ray-cast form factors.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "solver/scene/camera.h"
#include "solver/scene/mesh.h"

struct RTCDeviceTy;
struct RTCSceneTy;

namespace bumprad {

struct Hit {
  std::uint32_t element;
  double u, v;  // as vertex_radiosity.h's interpolate() expects
  double t;
  bool front;  // the ray met the element's lit side
};

class RayScene {
 public:
  explicit RayScene(const Mesh& mesh);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  // Nearest hit along the ray; safe to call from many threads at once.
  std::optional<Hit> intersect(const Ray& ray) const;
  // Whether anything lies on the ray before `distance` (a shadow ray); thread-safe too.
  bool occluded(const Ray& ray, double distance) const;
  const Mesh& mesh() const { return mesh_; }

 private:
  const Mesh& mesh_;
  RTCDeviceTy* device_ = nullptr;
  RTCSceneTy* scene_ = nullptr;
  std::vector<std::uint32_t> quad_elements_, triangle_elements_;  // primID -> element
  unsigned quad_geometry_ = 0, triangle_geometry_ = 0;
};

}  // namespace bumprad
