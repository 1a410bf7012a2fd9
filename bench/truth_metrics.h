// How benchmarks measure an image against a path-traced reference: relative RMS error over
// the lit surfaces (emitters' pixels masked) and over all pixels, and the brightness ratio.
#pragma once

#include <vector>

#include "solver/render/error_estimate.h"
#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"
#include "solver/scene/scene.h"
#include "solver/util/image.h"

namespace bumprad {

struct Comparison {
  double surfaces;    // relative RMS over pixels that show no emitter
  double all;         // relative RMS over every pixel
  double brightness;  // sum(a) / sum(r) over the surfaces' pixels
};

// sqrt(sum |a - r|^2 / sum |r|^2), linear radiance, every channel.
Comparison compare(const Image& a, const Image& r, const std::vector<bool>& emitter);

// Where a differs from r: per pixel, a / r - 1 of the 3 x 3 mean luminance, red where a is
// brighter and blue where darker, full at +-20 %; emitter pixels black. For finding where the
// error sits (shadow edges, corners, a face lit wrongly).
Image difference_image(const Image& a, const Image& r, const std::vector<bool>& emitter);

// Per pixel of scene.camera, the object its centre's camera ray meets first (-1: none).
std::vector<int> pixel_objects(const Scene& scene, const Mesh& mesh, const RayScene& rays);

// Speckle: the RMS of the high-pass (a pixel minus its 5 x 5 mean) of a's luminance minus
// b's, over the pixels whose 5 x 5 neighbourhood all show `object`, relative to b's mean
// luminance there. Against a converged b it is a's noise, not the detail both share (a hard
// shadow's edge); against the same render at another seed, sqrt(2) times b's own.
double speckle(const Image& a, const Image& b, const std::vector<int>& objects, int object);

// An error measured against a noisy reference, with the reference's own noise (relative
// RMS) taken out: independent errors add in squares.
double without_noise(double measured, double noise);

}  // namespace bumprad
