// Untiling: every pixel reads its value back from the sub-image it was shaded in (interleaved sampling).
#include "flc/flc_common.glsl"

layout(binding = 12) uniform sampler2D u_tiled;

layout(location = 0) out vec4 out_indirect;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  ivec2 tile = pixel % flc.tiles_per_axis;
  ivec2 local = pixel / flc.tiles_per_axis;
  out_indirect = texelFetch(u_tiled, tile * ivec2(flc.tile_width, flc.tile_height) + local, 0);
}
