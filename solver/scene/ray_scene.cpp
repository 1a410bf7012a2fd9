#include "solver/scene/ray_scene.h"

#include <embree3/rtcore.h>

#include <limits>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

namespace bumprad {
namespace {

// Builds one Embree geometry from the elements with `corners` vertices (3 or 4).
unsigned attach(RTCDevice device, RTCScene scene, const Mesh& mesh, int corners,
                std::vector<std::uint32_t>& prim_to_element) {
  for (std::uint32_t i = 0; i < mesh.elements.size(); ++i)
    if (mesh.elements[i].vertex_count == corners) prim_to_element.push_back(i);
  if (prim_to_element.empty()) return RTC_INVALID_GEOMETRY_ID;
  RTCGeometry g =
      rtcNewGeometry(device, corners == 4 ? RTC_GEOMETRY_TYPE_QUAD : RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) v[3 * i + k] = float(mesh.vertices[i].position[k]);
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_INDEX, 0, corners == 4 ? RTC_FORMAT_UINT4 : RTC_FORMAT_UINT3,
      corners * sizeof(unsigned), prim_to_element.size()));
  for (std::size_t p = 0; p < prim_to_element.size(); ++p)
    for (int k = 0; k < corners; ++k) idx[corners * p + k] = mesh.elements[prim_to_element[p]].v[k];
  rtcCommitGeometry(g);
  unsigned id = rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  return id;
}

}  // namespace

RayScene::RayScene(const Mesh& mesh) : mesh_(mesh) {
  device_ = rtcNewDevice(nullptr);
  if (!device_) throw std::runtime_error("Embree: cannot create a device");
  scene_ = rtcNewScene(device_);
  // Watertight: without it a ray along the diagonal that splits a quad, or along an edge
  // two elements share, can pass between them (seen: a mirror's centre pixel went black).
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  quad_geometry_ = attach(device_, scene_, mesh, 4, quad_elements_);
  triangle_geometry_ = attach(device_, scene_, mesh, 3, triangle_elements_);
  rtcCommitScene(scene_);
  if (rtcGetDeviceError(device_) != RTC_ERROR_NONE)
    throw std::runtime_error("Embree: cannot build the scene");
}

RayScene::~RayScene() {
  rtcReleaseScene(scene_);
  rtcReleaseDevice(device_);
}

std::optional<Hit> RayScene::intersect(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = float(ray.origin.x);
  rh.ray.org_y = float(ray.origin.y);
  rh.ray.org_z = float(ray.origin.z);
  rh.ray.dir_x = float(ray.direction.x);
  rh.ray.dir_y = float(ray.direction.y);
  rh.ray.dir_z = float(ray.direction.z);
  rh.ray.tnear = 0;
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  const auto& table = rh.hit.geomID == quad_geometry_ ? quad_elements_ : triangle_elements_;
  std::uint32_t element = table[rh.hit.primID];
  bool front = glm::dot(mesh_.elements[element].normal, ray.direction) < 0;
  return Hit{element, rh.hit.u, rh.hit.v, rh.ray.tfar, front};
}

bool RayScene::occluded(const Ray& ray, double distance) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r{};
  r.org_x = float(ray.origin.x);
  r.org_y = float(ray.origin.y);
  r.org_z = float(ray.origin.z);
  r.dir_x = float(ray.direction.x);
  r.dir_y = float(ray.direction.y);
  r.dir_z = float(ray.direction.z);
  r.tnear = 0;
  r.tfar = float(distance);
  r.mask = ~0u;
  rtcOccluded1(scene_, &context, &r);
  return r.tfar < 0;  // Embree marks an occluded ray with tfar = -inf
}

}  // namespace bumprad
