// Sampling images and colour textures over a surface's (u,v): bilinear, with wrap modes.
// Image height maps (bump.cpp) and colour textures (the view pass) share it.
#pragma once

#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "solver/scene/mesh.h"
#include "solver/scene/scene.h"
#include "solver/util/image.h"

namespace bumprad {

// Bilinear at p in image units ([0,1]^2 spans the image once, y down the rows).
Rgb sample_image(const Image& image, glm::dvec2 p, Wrap wrap);

// The texture's reflectance at surface coordinates uv (its colour, for an emission texture).
Rgb texture_reflectance(const ColorTexture& texture, glm::dvec2 uv);

// The emission the camera sees at uv: E, times the emission texture there if there is one.
Rgb emission_at(const Material& material, glm::dvec2 uv);

// Its mean reflectance over the whole texture.
Rgb texture_mean(const ColorTexture& texture);

// Per element, the diffuse reflectance the solve uses: a textured material's mean over the
// element (8 x 8 samples), so light bounces off a checker's light squares more than off its
// dark ones; otherwise the material's reflectance.
std::vector<Rgb> element_reflectance(const Mesh& mesh, std::span<const Material> materials);

}  // namespace bumprad
