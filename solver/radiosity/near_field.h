// Indirect light near creases and contacts. Interpolating vertex radiosity assumes the light
// a surface receives changes linearly across an element; where another surface meets it (a
// ceiling along a wall, a floor beside a box) it does not: that surface fills a solid angle
// that grows quickly as a point nears it, and the crease comes out too bright. Per vertex,
// the elements of other surfaces within one and a half element sizes (its near set) are taken out
// of the interpolation and put back exactly at each shaded point: point-to-polygon form factors
// (Lambert) times their radiosity, in place of the rest of the scene's light in the solid
// angle they cover; far from the point (in their own sizes), a tree node of them at a time.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <stop_token>
#include <vector>

#include <glm/vec3.hpp>

#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"

namespace bumprad {

// The near sets and their form factors averaged over each vertex's elements: geometry
// only, built once per mesh.
class NearField {
 public:
  // `open` (per element, open_share(); empty: all open) weighs elements into vertices as
  // vertex_radiosity() does. `stop` ends it early, its near sets then partial.
  NearField(const Mesh& mesh, const RayScene& rays, std::span<const double> open,
            std::stop_token stop = {});

  struct Term {
    std::uint32_t element;    // of another surface, facing the vertex's elements
    float radius;             // the element's: how far its farthest corner lies from its centroid
    double mean_form_factor;  // from the vertex's elements, averaged as its value is
  };
  // A vertex's terms, in the order of their elements.
  std::span<const Term> terms(std::uint32_t vertex) const {
    return {terms_.data() + first_[vertex], terms_.data() + first_[vertex + 1]};
  }
  // An element's corners' terms merged: each of their elements once, with the corners
  // (bit k: corner k) whose near sets hold it, so that a shaded point finds each form
  // factor once for all its corners; in the order of term_nodes' trees.
  struct CornerTerm {
    std::uint32_t element;
    float radius;
    std::uint8_t corners;
  };
  std::span<const CornerTerm> corner_terms(std::uint32_t element) const {
    return {corner_terms_.data() + corner_first_[element],
            corner_terms_.data() + corner_first_[element + 1]};
  }
  // An element's corner terms as trees, one for each set of corners, so that a shaded point
  // far from a node's terms (in the node's radii) takes them as one small patch: beside a
  // finely cut model, a coarse floor element's corners hold thousands of its triangles.
  // Nodes are laid out depth first; a node's children follow it, and `skip` is the node
  // after its subtree (a leaf's: the next one).
  struct TermNode {
    Vec3 centre;            // its terms' elements' area-weighted centroid
    float radius;           // of a sphere about `centre` that holds its terms' elements
    glm::vec3 vector_area;  // sum of A_j n_j
    float cone_cos;         // of the widest angle between an element's normal and vector_area
    float cone_sin;
    std::uint32_t first;  // its terms: corner_terms(element)[first, first + count)
    std::uint32_t count;
    std::uint32_t skip;    // index in term_nodes(element)
    std::uint8_t corners;  // the corners all its terms belong to
  };
  std::span<const TermNode> term_nodes(std::uint32_t element) const {
    return {nodes_.data() + node_first_[element], nodes_.data() + node_first_[element + 1]};
  }
  // The index in all elements' nodes, laid end to end, of term_nodes(element)'s first.
  std::uint32_t first_node(std::uint32_t element) const { return node_first_[element]; }
  // The sum of a vertex's mean form factors: the share of its view the near set fills.
  double covered(std::uint32_t vertex) const { return covered_[vertex]; }
  // What an element's light is multiplied by over its open part, which holds all of it
  // (one over its open share; 1 where all open or all buried).
  double open_gain(std::uint32_t element) const {
    return open_gain_.empty() ? 1 : open_gain_[element];
  }
  const Mesh& mesh() const { return mesh_; }

 private:
  const Mesh& mesh_;
  std::vector<std::uint32_t> first_;  // per vertex, into terms_; one past the end last
  std::vector<Term> terms_;
  std::vector<std::uint32_t> corner_first_;  // per element, into corner_terms_; one past last
  std::vector<CornerTerm> corner_terms_;
  std::vector<std::uint32_t> node_first_;  // per element, into nodes_; one past last
  std::vector<TermNode> nodes_;
  std::vector<double> covered_;
  std::vector<float> open_gain_;  // per element, or empty: all open
};

// A NearField lit by one solution: what the view pass adds to the interpolated indirect
// light at a point.
class NearFieldShading {
 public:
  // `reflected`: each element's reflected radiosity, B - E, spread over its whole area as
  // the solve gives it. A point beside an element partly buried sees its open part only,
  // which holds all of it (a floor element half under a box: the box's face at the floor
  // had half its light: 19 % too dark at the foot of cornell's tall block, 11 % after).
  NearFieldShading(const NearField& near, std::span<const Rgb> reflected);

  // The change to the interpolated reflected radiosity at `point` (smooth normal `normal`)
  // of `element` (the mesh's own, by reference: its index is its place there), whose corners
  // weigh `weights` and hold `vertex_values` (what the view pass interpolates) and whose
  // mean diffuse reflectance is `reflectance`.
  Rgb correction(const Element& element, const std::array<double, 4>& weights, const Vec3& point,
                 const Vec3& normal, const Rgb& reflectance,
                 std::span<const Rgb> vertex_values) const;

 private:
  const NearField& near_;
  std::span<const Rgb> reflected_;
  std::vector<Rgb> near_light_;  // per vertex: sum of B_j times its mean form factor
  // Per term node (NearField::first_node), per channel: sum of A_j B_j n_j (B_j with its
  // open gain).
  std::vector<std::array<glm::vec3, 3>> node_light_;
};

}  // namespace bumprad
