// Adaptive subdivision (Cohen, Greenberg, Immel & Brock 1986): elements whose radiosity
// differs too much from a neighbour's are split in four, where shadows and light change
// fast, instead of meshing the whole scene finely. Patches keep their elements contiguous,
// so they shoot as before; only receivers are refined.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "solver/scene/mesh.h"

namespace bumprad {

// Elements to split: those whose luminance differs from a neighbour's (sharing a vertex)
// by more than `threshold` of the brighter of the two. Differences among elements darker
// than 1 % of the mean luminance are ignored: they do not show.
std::vector<std::uint32_t> elements_to_split(const Mesh& mesh, std::span<const Rgb> radiosity,
                                             double threshold);

// `mesh` with each listed element split in four (quads at their edge midpoints and centre,
// triangles at their edge midpoints). New vertices interpolate position, (u,v), tangents
// and the smooth normal; an unsplit neighbour is left with a T-vertex on its edge.
Mesh subdivide(const Mesh& mesh, std::span<const std::uint32_t> split);

}  // namespace bumprad
