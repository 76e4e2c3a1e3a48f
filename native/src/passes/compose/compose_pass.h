// Adds each sample's AOVs (Combined = direct + emission, or the background) into accumulation targets and
// reads their average back. Shaders: shaders/common/fullscreen.vert, shaders/compose/compose.frag.
#pragma once

#include <array>
#include <vector>

#include "frame.h"
#include "gl/objects.h"
#include "passes/gbuffer/gbuffer_pass.h"
#include "passes/render_context.h"

namespace bounce {

class ComposePass {
 public:
  ComposePass();
  // Accumulation slots: each holds one tile's sums. One tile, or tiles that keep their sums on the GPU across
  // samples, take a slot each; tiles that take turns share slot 0. Slots from `count` on are freed.
  void keep_slots(int count);
  static constexpr double kBytesPerPixel = 9 * 16 + 4;  // a slot's targets: RGBA32F AOVs and R32F Depth
  void clear(int slot, int width, int height);
  // What an indirect method hands over; textures are 0 where it has none.
  struct Indirect {
    GLuint light = 0;  // reflected radiance, or irradiance / pi when times_albedo
    bool times_albedo = false;
    GLuint vpls = 0;               // debug view
    GLuint second_bounce = 0;      // irradiance / pi
    GLuint near_field = 0;         // irradiance / pi of the first bounce, added to `light` (NearFieldPass)
    GLuint near_field_second = 0;  // irradiance / pi of the second bounce, added to `light` and `second_bounce`
  };
  void accumulate(int slot, const RenderContext& context, const GBuffer& gbuffer, GLuint direct,
                  const Indirect& indirect);
  // Replace: averages `samples` accumulated samples of every AOV `frame` holds into it at the pixel offset (x, y).
  // Add: the targets hold one sample of `samples`, added to what the frame holds (Depth: the nearest), for tiles
  // that take turns with the targets. Frame::zero_nonfinite then clears what is not finite.
  enum class Into { Replace, Add };
  void read(int slot, int samples, Frame& frame, int x, int y, Into into = Into::Replace);

 private:
  static constexpr int kComposedAovs = 8;  // written by compose.frag at once (GL guarantees 8 draw buffers)
  struct Targets {
    std::array<gl::Texture, BOUNCE_AOV_COUNT> textures;
    gl::Framebuffer framebuffer, second_bounce_framebuffer;
    int width = 0, height = 0;
  };

  gl::Program program_, add_times_albedo_;
  std::vector<Targets> slots_;
  gl::TextureReadback readback_;
};

}  // namespace bounce
