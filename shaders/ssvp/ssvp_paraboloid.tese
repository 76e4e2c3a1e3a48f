// Paraboloid map, tessellation evaluation: the Heidrich-Seidel projection about the cluster's normal. Clip space
// is homogeneous (w = 1 + d.z), so the division gives d.xy / (1 + d.z) and nothing blows up behind the map; the
// clip distance d.z cuts the hemisphere's horizon. Depth: distance / far.
#include "ssvp/ssvp_common.glsl"

layout(triangles, equal_spacing, ccw) in;

layout(location = 10) uniform int u_cluster;

in vec3 c_world_position[];
in vec3 c_world_normal[];
in vec2 c_uv[];
out vec3 v_world_position;
out vec3 v_world_normal;
out vec2 v_uv;

out float gl_ClipDistance[1];

void main() {
  vec3 b = gl_TessCoord;
  v_world_position = b.x * c_world_position[0] + b.y * c_world_position[1] + b.z * c_world_position[2];
  v_world_normal = b.x * c_world_normal[0] + b.y * c_world_normal[1] + b.z * c_world_normal[2];
  v_uv = b.x * c_uv[0] + b.y * c_uv[1] + b.z * c_uv[2];
  vec3 local = cluster_local(u_cluster, v_world_position);
  float distance = length(local);
  vec3 d = distance > 0.0 ? local / distance : vec3(0.0, 0.0, -1.0);
  float w = 1.0 + d.z;
  gl_Position = vec4(d.xy, (2.0 * distance / ssvp.paraboloid_far - 1.0) * w, w);
  gl_ClipDistance[0] = d.z;
}
