// Sampling images and colour textures over a surface's (u,v): bilinear, with wrap modes.
// Image height maps (bump.cpp) and colour textures (the view pass) share it.
#pragma once

#include <glm/vec2.hpp>

#include "solver/image.h"
#include "solver/scene.h"

namespace bumprad {

// Bilinear at p in image units ([0,1]^2 spans the image once, y down the rows).
Rgb sample_image(const Image& image, glm::dvec2 p, Wrap wrap);

// The texture's reflectance at surface coordinates uv.
Rgb texture_reflectance(const ColorTexture& texture, glm::dvec2 uv);

// Its mean reflectance over the surface: what the solve uses.
Rgb texture_mean(const ColorTexture& texture);

}  // namespace bumprad
