// Paraboloid map, fragment stage: what the cluster sees in each direction of its hemisphere: the surface's
// position and distance (the cluster's indirect shadows), its normal facing the cluster, and its albedo (the
// second bounce's sources). The position is where this texel's own direction meets the triangle's plane, so
// depths stay exact inside triangles that the straight rasterization distorts.
#include "common/scene.glsl"
#include "ssvp/ssvp_common.glsl"

layout(location = 10) uniform int u_cluster;

in vec3 v_world_position;
in vec3 v_world_normal;
in vec2 v_uv;

layout(location = 0) out vec4 out_position;  // xyz world position, w distance to the cluster centre
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_albedo;    // rgb albedo, a coverage

void main() {
  vec4 base = surface_base_color(v_uv);
  if (surface_is_cut_out(base.a)) discard;
  Cluster cluster = clusters[u_cluster];
  vec3 centre = cluster.position_first.xyz;
  vec3 local = ssvp_paraboloid_direction(gl_FragCoord.xy / float(ssvp.paraboloid_size) * 2.0 - 1.0);
  vec3 direction = local.x * cluster.tangent.xyz + local.y * cluster.bitangent.xyz + local.z * cluster.normal_count.xyz;
  vec3 plane_normal = cross(dFdx(v_world_position), dFdy(v_world_position));
  float facing = dot(direction, plane_normal);
  vec3 position = v_world_position;
  if (abs(facing) > 1e-3 * length(plane_normal)) {
    float t = dot(v_world_position - centre, plane_normal) / facing;
    if (t > 0.0) position = centre + t * direction;
  }
  vec3 to_centre = centre - position;
  vec3 n = normalize(v_world_normal);
  if (any(isnan(n))) n = normalize(to_centre);
  if (dot(n, to_centre) < 0.0) n = -n;
  out_position = vec4(position, length(to_centre));
  out_normal = vec4(n, 0.0);
  out_albedo = vec4(base.rgb, 1.0);
}
