// Depth only. Cut-outs (leaves, chains) let light through their holes exactly where the G-buffer does.
#include "common/scene.glsl"

in vec2 v_uv;

void main() {
  if (surface_is_cut_out(surface_base_color(v_uv).a)) discard;
}
