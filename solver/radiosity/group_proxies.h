// Coarse stand-ins for a model's groups of small triangles (mesh.h), for hemi-cubes that see
// them from afar: a shot's item buffer drew every one of a fine model's triangles, far below
// its pixels, and at 100k triangles that drawing was most of what a shot's cost grew by.
// Vertex clustering (Rossignac & Borrel 1993) at a few cell sizes, each group's error measured.
#pragma once

#include <array>
#include <cstdint>
#include <stop_token>
#include <vector>

#include <glm/vec3.hpp>

#include "solver/scene/mesh.h"

namespace bumprad {

struct ProxyTriangle {
  std::array<glm::vec3, 3> corners;
  glm::vec3 centroid, normal;  // for culling: drawn where the normal faces the eye
  std::uint32_t element;       // the element it was made from: the id it is drawn with
};

// The groups' proxies at one cell size.
struct ProxyLevel {
  struct Group {
    std::uint32_t first = 0, count = 0;  // its triangles; none: no proxy at this level
    std::uint32_t skirt_first = 0, skirt_count = 0;
    // How far any of the group's vertices lies from the proxies' surface: the proxy may
    // stand for the group where this is small against a pixel as far off as it is seen.
    double error = 0;
  };
  std::vector<Group> groups;  // per mesh group
  std::vector<ProxyTriangle> triangles;
  // Where a group meets another, the strip from its sides to their image on its proxy: to be
  // drawn with the proxy while the other group (skirt_neighbour, per skirt) is drawn some
  // other way (as it is, or at another level), so that no crack opens between the two.
  std::vector<ProxyTriangle> skirts;
  std::vector<std::uint32_t> skirt_neighbour;
};

struct GroupProxies {
  std::vector<ProxyLevel> levels;  // finest first
  struct Sphere {
    Vec3 centre{0};
    double radius = 0;
  };
  std::vector<Sphere> spheres;  // per group: about its vertices and its proxies' corners
};

// Proxies for the groups `eligible` marks (per group; any other size: none). A group gets
// one at a level where it holds enough elements for the proxy to save drawing. The clusters
// are cells 2, 4 and 8 of its surface's typical triangle sides wide, split by the vertices'
// normals and by the surface's outline, and shared by all groups of the surface, so that
// neighbouring proxies of one level meet without cracks. `stop` ends it early with none.
GroupProxies group_proxies(const Mesh& mesh, const std::vector<bool>& eligible,
                           std::stop_token stop = {});

}  // namespace bumprad
