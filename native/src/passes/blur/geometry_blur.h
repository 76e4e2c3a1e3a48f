// Geometry-aware separable blur (shaders/blur/geometry_blur.frag): a Gaussian whose taps count only where the
// neighbour lies on the receiver's surface. The indirect passes recombine their interleaved pixels with it.
#pragma once

#include "gl/objects.h"
#include "passes/gbuffer/gbuffer_pass.h"

namespace bounce {

class GeometryBlur {
 public:
  GeometryBlur();
  // Blurs `source` (RGBA32F, the G-buffer's size) over `radius` pixels; returns the blurred texture, which
  // stays valid until the next call, or `source` itself when radius is 0.
  GLuint run(GLuint source, const GBuffer& gbuffer, int radius);

 private:
  gl::Program program_;
  gl::Texture temp_, result_;
  gl::Framebuffer temp_target_, result_target_;
  int width_ = 0, height_ = 0;
};

}  // namespace bounce
