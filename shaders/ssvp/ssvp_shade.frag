// Interleaved shading (Sec. II-C): the pixel at (x mod T, y mod T) of its T x T tile takes every T^2-th VPL,
// starting at an offset that turns with the progressive sample, weighted by T^2. Each VPL gives its irradiance
// (vpl_irradiance in ssvp_common.glsl: flux / pi G, G capped) times the clustered visibility: whether x is seen
// from the centre of the VPL's cluster in its paraboloid map.
// Outputs irradiance / pi (the compose pass multiplies the albedo): both bounces, and the second alone.
#include "ssvp/ssvp_common.glsl"

layout(binding = 1) uniform sampler2D g_albedo;
layout(binding = 2) uniform sampler2D g_normal;
layout(binding = 3) uniform sampler2D g_position;
layout(binding = 13) uniform sampler2DArray paraboloid_position;

layout(location = 0) out vec4 out_indirect;
layout(location = 1) out vec4 out_second;

// 1 if x is seen from cluster c's centre. Receivers behind the map's hemisphere get 1: the map knows nothing of
// them and the VPL's own cosine decides. Against self-shadowing, the receiver is pushed off its surface by a
// texel's footprint at its distance, and depths up to a footprint x (1 + tan of the incidence) beyond the stored
// one still count as seen: a surface seen at a grazing angle spans that much depth within one texel.
float cluster_visibility(int c, vec3 x, vec3 n) {
  vec3 local = cluster_local(c, x);
  float r = length(local);
  if (local.z <= 0.0 || r == 0.0) return 1.0;
  vec2 p = ssvp_paraboloid_point(local / r);
  float footprint = r * 4.0 / (float(ssvp.paraboloid_size) * (1.0 + dot(p, p)));
  vec3 from_centre = x - clusters[c].position_first.xyz;
  float cos_incidence = max(abs(dot(n, from_centre)) / r, 0.05);
  float tolerance = footprint * (1.0 + sqrt(1.0 - cos_incidence * cos_incidence) / cos_incidence);
  local = cluster_local(c, x + n * footprint);
  r = length(local);
  if (local.z <= 0.0) return 1.0;
  vec4 seen = texelFetch(paraboloid_position, ivec3(paraboloid_texel(ssvp_paraboloid_point(local / r)), c), 0);
  if (seen.w == 0.0) return 1.0;  // nothing in that direction
  return r <= seen.w + tolerance ? 1.0 : 0.0;
}

vec3 vpl_light(Vpl vpl, vec3 x, vec3 n) {
  vec3 e = vpl_irradiance(vpl, x, n);
  if (e == vec3(0.0)) return e;
  return e * cluster_visibility(int(vpl.position_cluster.w), x, n);
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  out_indirect = out_second = vec4(0.0);
  if (texelFetch(g_albedo, pixel, 0).a == 0.0) return;
  vec3 x = texelFetch(g_position, pixel, 0).xyz;
  vec3 n = texelFetch(g_normal, pixel, 0).xyz;
  int t = ssvp.tiles_per_axis;
  int share = t * t;
  ivec2 in_tile = pixel % t;
  int start = (in_tile.x + t * in_tile.y + ssvp.pattern_rotation) % share;
  vec3 first = vec3(0.0), second = vec3(0.0);
  for (int i = start; i < ssvp.first_count; i += share) first += vpl_light(first_vpls[i], x, n);
  if (ssvp.bounces > 1)
    for (int i = start; i < ssvp.second_count; i += share) second += vpl_light(second_vpls[i], x, n);
  first *= float(share) / SSVP_PI;
  second *= float(share) / SSVP_PI;
  out_indirect = vec4(first + second, 0.0);
  out_second = vec4(second, 0.0);
}
