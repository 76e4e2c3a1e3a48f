// Paraboloid map, tessellation control: straight edges should bend under the paraboloid projection, so an edge
// spanning a wide angle as seen from the cluster is split into pieces of at most MAX_EDGE_ANGLE. Its level depends
// on the edge alone, so neighbouring triangles agree and no crack opens. The fragment stage makes depths exact
// inside each piece, so pieces may be coarse; triangles wholly behind the hemisphere are culled here.
#include "ssvp/ssvp_common.glsl"

layout(vertices = 3) out;

layout(location = 10) uniform int u_cluster;
layout(location = 11) uniform float u_max_tess_level;

in vec3 v_world_position[];
in vec3 v_world_normal[];
in vec2 v_uv[];
out vec3 c_world_position[];
out vec3 c_world_normal[];
out vec2 c_uv[];

const float MAX_EDGE_ANGLE = 0.25;  // radians: the chord of such an arc of the rim strays 0.8 % of its radius

float edge_level(vec3 a, vec3 b) {
  vec3 centre = clusters[u_cluster].position_first.xyz;
  vec3 da = a - centre, db = b - centre;
  float angle = atan(length(cross(da, db)), dot(da, db));
  return clamp(ceil(angle / MAX_EDGE_ANGLE), 1.0, u_max_tess_level);
}

void main() {
  c_world_position[gl_InvocationID] = v_world_position[gl_InvocationID];
  c_world_normal[gl_InvocationID] = v_world_normal[gl_InvocationID];
  c_uv[gl_InvocationID] = v_uv[gl_InvocationID];
  if (gl_InvocationID == 0) {
    bool behind = cluster_local(u_cluster, v_world_position[0]).z < 0.0 &&
                  cluster_local(u_cluster, v_world_position[1]).z < 0.0 &&
                  cluster_local(u_cluster, v_world_position[2]).z < 0.0;
    // Outer level i is the edge opposite vertex i; level 0 discards the patch.
    gl_TessLevelOuter[0] = behind ? 0.0 : edge_level(v_world_position[1], v_world_position[2]);
    gl_TessLevelOuter[1] = behind ? 0.0 : edge_level(v_world_position[2], v_world_position[0]);
    gl_TessLevelOuter[2] = behind ? 0.0 : edge_level(v_world_position[0], v_world_position[1]);
    gl_TessLevelInner[0] = max(gl_TessLevelOuter[0], max(gl_TessLevelOuter[1], gl_TessLevelOuter[2]));
  }
}
