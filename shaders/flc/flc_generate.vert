// Regular pipeline, vertex stage: world-space corners with their per-vertex random (Sec. 6, Alg. 2).
#include "common/random.glsl"
#include "common/scene.glsl"

layout(location = 0) in vec3 a_position;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in uint a_random;

out vec3 v_world_position;
out vec2 v_uv;
flat out uint v_random;
flat out uint v_instance_random;

void main() {
  uint instance = instance_lists[u_instance_offset + gl_InstanceID];
  v_world_position = (instances[instance].object_to_world * vec4(a_position, 1.0)).xyz;
  v_uv = a_uv;
  v_random = a_random;
  v_instance_random = pcg_hash(instance * 0x9e3779b9u + 0x7f4a7c15u);
  gl_Position = vec4(0.0);
}
