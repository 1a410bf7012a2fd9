// Clusters (Smits, Arvo & Greenberg 1994; Sillion 1995): a small convex object with a curved
// surface (a ball, a bead, a pebble) shoots the light of all its patches in one shot, from
// its centre, each patch's light leaving in the lobes of its elements' normals. A ball of
// six patches takes one shot instead of six, and its two half hemi-cubes are drawn once.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "solver/scene/mesh.h"
#include "solver/scene/scene.h"

namespace bumprad {

struct Cluster {
  std::uint32_t object = 0;
  std::vector<std::uint32_t> patches;  // its members
  Vec3 centre{0};                      // the area-weighted centroid of its elements
  double radius = 0;                   // its farthest vertex from the centre
};

// The mesh's clusters: the objects that are (a) two patches or more, curved (geometry.h) but
// for slivers; (b) closed and convex: every edge shared by two of its elements, neither
// with a corner in front of the other's plane; (c) no wider than the scene's natural patch
// (a sixteenth of its diagonal); (d) diffuse: specular transfer reflects from a patch's own
// hemi-cube; (e) open to the scene but for slivers (`open`, per element its open share,
// vertex_radiosity.h; empty: all open): a ball sunk into a floor has its centre there.
std::vector<Cluster> find_clusters(const Mesh& mesh, const std::vector<Material>& materials,
                                   std::span<const double> open = {});

// How a member's light leaves the cluster: a direction w gets the share sum over lobes of
// max(0, lobe . w) / pi per steradian. One lobe per 24th of the sphere of normals (a cube
// map's faces in quarters): the sum over its elements of weight x normal, the whole scaled
// to integrate to 1 over the sphere. Exact where a lobe's elements all face w or all face
// away; within a quarter's spread of their horizon the light is placed a little off, never
// made or lost (a uniform ball's light in any direction within 4.5 %; one lobe a patch, its
// normals summed, was 32 % off). `weight` per element of the patch (the power it shoots;
// all zero: its area).
std::vector<Vec3> member_lobes(const Mesh& mesh, const Patch& patch,
                               std::span<const double> weight);

// F from a member to an element as a point at the cluster's centre sends it: the lobes'
// intensity toward the element times the solid angle it fills, at its centroid or, near the
// centre, averaged over its part points (geometry.h).
double cluster_form_factor(const Mesh& mesh, std::span<const Vec3> lobes, const Vec3& centre,
                           const Element& e);

}  // namespace bumprad
