// An offscreen OpenGL context (OSMesa, llvmpipe) that renders into a buffer it owns, so
// item-buffer pixels are read in place after glFinish with no copy.
#pragma once

#include <cstdint>
#include <vector>

struct osmesa_context;

namespace bumprad {

class GlContext {
 public:
  // Throws std::runtime_error when no context can be made.
  GlContext(int width, int height);
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Binds the context to the calling thread; call before any GL command.
  void make_current();
  // RGBA8 pixels, row 0 at the bottom, valid after glFinish.
  const std::uint32_t* pixels() const { return buffer_.data(); }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  osmesa_context* context_ = nullptr;
  std::vector<std::uint32_t> buffer_;
  int width_, height_;
};

}  // namespace bumprad
