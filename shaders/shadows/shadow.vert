#include "common/scene.glsl"

layout(location = 0) in vec3 a_position;
layout(location = 2) in vec2 a_uv;

out vec2 v_uv;

void main() {
  v_uv = a_uv;
  gl_Position = u_view_projection * (current_instance().object_to_world * vec4(a_position, 1.0));
}
