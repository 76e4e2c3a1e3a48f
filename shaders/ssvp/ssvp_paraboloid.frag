// Paraboloid map, fragment: what the cluster sees in each direction of its hemisphere: the surface's position
// and distance (the cluster's indirect shadows), its normal facing the cluster, and its albedo (the second
// bounce's sources).
#include "common/scene.glsl"
#include "ssvp/ssvp_common.glsl"

layout(location = 10) uniform int u_cluster;

in vec3 e_world_position;
in vec3 e_world_normal;
in vec2 e_uv;

layout(location = 0) out vec4 out_position;  // xyz world position, w distance to the cluster centre
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_albedo;    // rgb albedo, a coverage

void main() {
  vec4 base = surface_base_color(e_uv);
  if (surface_is_cut_out(base.a)) discard;
  vec3 to_centre = clusters[u_cluster].position_first.xyz - e_world_position;
  vec3 n = normalize(e_world_normal);
  if (any(isnan(n))) n = normalize(to_centre);
  if (dot(n, to_centre) < 0.0) n = -n;
  out_position = vec4(e_world_position, length(to_centre));
  out_normal = vec4(n, 0.0);
  out_albedo = vec4(base.rgb, 1.0);
}
