// Meshing: scene objects become smooth surfaces, patches (which shoot) and elements (planar
// quads or triangles, which receive). Vertices are shared within a surface, never across a
// crease, so vertex radiosity is averaged only where the surface is smooth.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <stop_token>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>

#include "solver/scene/scene.h"

namespace bumprad {

struct Vertex {
  Vec3 position;
  Vec3 normal;      // area-weighted mean of the adjacent element normals
  glm::dvec2 uv;    // the surface's own (u,v) parameterisation in [0,1]^2
  Vec3 dpdu, dpdv;  // parametric derivatives: the tangent frame for bump perturbation
};

struct Element {
  std::array<std::uint32_t, 4>
      v{};  // counter-clockwise seen from the front; v[3] unused if triangle
  int vertex_count = 4;
  std::uint32_t patch = 0;
  std::uint32_t group = 0;
  std::uint32_t surface = 0;
  std::uint32_t object = 0;
  int material = 0;
  Vec3 centroid{0};
  Vec3 normal{0};
  double area = 0;
};

// Contiguous elements [first, first + count) with their area, area-weighted centroid and
// normal.
struct ElementRun {
  std::uint32_t first = 0;
  std::uint32_t count = 0;
  Vec3 centroid{0};
  Vec3 normal{0};
  double area = 0;
};

// A patch shoots light through one hemi-cube.
using Patch = ElementRun;
// A group receives it as one where a model's triangles are finer than the scene needs: the
// elements of one patch that fall in one cell of the element size, facing alike
// (shot_form_factors.cpp). Elsewhere each element is a group of its own. Groups lie within
// patches, in order.
using ElementGroup = ElementRun;

struct Mesh {
  std::vector<Vertex> vertices;
  std::vector<Element> elements;
  std::vector<Patch> patches;
  std::vector<ElementGroup> groups;
  std::uint32_t surface_count = 0;
  Vec3 bounds_min{0};
  Vec3 bounds_max{0};

  double diagonal() const;
};

// An axis-aligned box around the object (a mesh without positions: an empty one, lo > hi).
std::pair<Vec3, Vec3> object_bounds(const Object& object);

// The element size a scene uses where an object does not say: the solver setting, or a
// sixteenth of the bounding-box diagonal of all objects.
double default_element_size(const Scene& scene);
// Per object, the size it is meshed at where it does not say: default_element_size(), or
// finer on a quad that a smaller chunky object touches (see the definition).
std::vector<double> object_element_sizes(const Scene& scene);

// The number of elements build_mesh will make for `object` (an upper bound: welding at
// poles only removes), so that oversized scenes are refused before memory is spent.
std::size_t estimate_element_count(const Object& object, double default_size);

// The patches (shooters) build_mesh will make for each object of `scene`: how many, what a
// progressive solve's shot count grows with (solver/cost.cpp), and about how wide.
struct PatchEstimate {
  std::size_t count = 0;
  double side = 0;         // k element sides, k elements a patch side
  double element = 0;      // an element's side
  std::size_t groups = 0;  // of a mesh's triangles of at most one element (Mesh::groups)
};
std::vector<PatchEstimate> estimate_patches(const Scene& scene);

// `stop` ends it between objects and between a mesh's triangles; the mesh is then partial,
// good for nothing but to be thrown away.
Mesh build_mesh(const Scene& scene, std::stop_token stop = {});

}  // namespace bumprad
