#include "common/scene.glsl"

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;

out vec3 v_world_position;
out vec3 v_world_normal;
out vec2 v_uv;

void main() {
  Instance instance = current_instance();
  vec4 world = instance.object_to_world * vec4(a_position, 1.0);
  v_world_position = world.xyz;
  v_world_normal = mat3(instance.normal_to_world) * a_normal;
  v_uv = a_uv;
  gl_Position = u_view_projection * world;
}
