#include "solver/util/gl_context.h"

#include <cstdlib>
#include <mutex>
#include <stdexcept>

#include <GL/osmesa.h>

namespace bumprad {
namespace {

// llvmpipe reads LP_NUM_THREADS once, when its first context is created; a user's value
// wins. 0 rasterises on the calling thread: for hemi-cube-sized buffers the hand-off to
// rasteriser threads costs more than it saves (paper-room at 150^2 on 2 cores: 1.74 ms a
// render with 0 threads, 2.32 ms with 2), and solver jobs run in parallel anyway.
void configure_llvmpipe_once() {
  static std::once_flag once;
  std::call_once(once, [] { setenv("LP_NUM_THREADS", "0", /*overwrite=*/0); });
}

}  // namespace

GlContext::GlContext(int width, int height)
    : buffer_(std::size_t(width) * std::size_t(height)), width_(width), height_(height) {
  configure_llvmpipe_once();
  // Ask for a 32-bit depth buffer; llvmpipe gives 24 bits regardless (GL_DEPTH_BITS), so
  // the hemi-cube's near plane is what keeps surfaces a millimetre apart (hemicube.cpp).
  context_ = OSMesaCreateContextExt(OSMESA_RGBA, 32, 0, 0, nullptr);
  if (!context_) context_ = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (!context_) throw std::runtime_error("OSMesa: could not create an offscreen GL context");
  make_current();
}

GlContext::~GlContext() {
  OSMesaDestroyContext(context_);
}

void GlContext::make_current() {
  if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, width_, height_))
    throw std::runtime_error("OSMesa: could not bind the offscreen GL context");
}

}  // namespace bumprad
