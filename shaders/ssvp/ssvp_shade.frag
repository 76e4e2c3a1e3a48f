// Interleaved shading (Sec. II-C): the pixel at (x mod T, y mod T) of its T x T tile takes every T^2-th VPL,
// starting at an offset that turns with the progressive sample, weighted by T^2. Each VPL gives its irradiance
// (vpl_irradiance in ssvp_common.glsl: flux / pi G, G capped) times the clustered visibility: the share of x seen
// from the centre of the VPL's cluster in its paraboloid map.
// With Ray Checks, a random share of the pairs goes to the CPU with the map's verdict, where a shadow ray from the
// VPL itself corrects it (native/src/passes/ray_checks/ray_checks.h).
// Outputs irradiance / pi (the compose pass multiplies the albedo): both bounces, and the second alone.
#include "ray_checks/ray_checks.glsl"
#include "ssvp/ssvp_common.glsl"

layout(binding = 1) uniform sampler2D g_albedo;
layout(binding = 2) uniform sampler2D g_normal;
layout(binding = 3) uniform sampler2D g_position;
layout(binding = 13) uniform sampler2DArray paraboloid_position;
layout(binding = 14) uniform sampler2DArray paraboloid_normal;

layout(location = 0) out vec4 out_indirect;
layout(location = 1) out vec4 out_second;

// Whether the point at distance r along `direction` from cluster c's centre lies in front of what the map's
// texel saw: compared with the depth, along that direction, of the plane of the surface the texel saw (its
// position and normal), exact for a plane however grazing. `tolerance` counts only where that surface faces the
// way the receiver's normal n does (within 60 degrees), so may be the receiver's own (self-shadowing): a receiver
// just behind another surface, in the next room beyond a single-faced wall, is behind it (with it everywhere, half a
// footprint of the next room's floor and walls along the wall took the lit room's light, 3-16 times Cycles' in the
// last 5 pixels before the corner, in the budget's two rooms). A plane seen nearly edge-on gives no such depth:
// the texel centre's own depth then stands, with `edge_on_tolerance`.
bool in_front_of_texel(ivec3 texel, vec3 centre, vec3 direction, float r, vec3 n, float tolerance,
                       float edge_on_tolerance) {
  vec4 seen = texelFetch(paraboloid_position, texel, 0);
  if (seen.w == 0.0) return true;  // nothing in that direction
  vec3 seen_normal = texelFetch(paraboloid_normal, texel, 0).xyz;  // faces the centre
  float facing = dot(direction, seen_normal);
  float own_surface_tolerance = dot(seen_normal, n) > 0.5 ? tolerance : 0.0;
  if (facing < -0.1) return r <= dot(seen.xyz - centre, seen_normal) / facing + own_surface_tolerance;
  return r <= seen.w + edge_on_tolerance;
}

// The share of x seen from cluster c's centre. Receivers behind the map's hemisphere get 1: the map knows nothing
// of them and the VPL's own cosine decides. Against self-shadowing, the receiver is pushed off its surface by a
// texel's footprint at its distance, and half a footprint more is left for curved surfaces and edges. The 2 x 2
// texels nearest its direction each decide, weighed bilinearly (percentage-closer filtering), so that a texel
// whose centre looks just past a wall's end (a wall standing on a floor that runs on under it) counts for its
// share only. The texel centre's depth alone, with a tolerance of a footprint x the tangent of the incidence for
// grazing planes, let a lit room's light through a thin wall along every corner of the next (the budget's two
// rooms: 1.8 times Cycles on the side walls, 1.05-1.13 now). Requiring all four texels to see the receiver
// shadowed a texel's width more around every occluder (Sponza's first bounce 0.94 -> 0.88 of Cycles).
float cluster_visibility(int c, vec3 x, vec3 n) {
  vec3 centre = clusters[c].position_first.xyz;
  vec3 local = cluster_local(c, x);
  float r = length(local);
  if (local.z <= 0.0 || r == 0.0) return 1.0;
  vec2 p = ssvp_paraboloid_point(local / r);
  float footprint = r * 4.0 / (float(ssvp.paraboloid_size) * (1.0 + dot(p, p)));
  float cos_incidence = max(abs(dot(n, x - centre)) / r, 0.05);
  float edge_on_tolerance = footprint * (1.0 + sqrt(1.0 - cos_incidence * cos_incidence) / cos_incidence);
  vec3 pushed = x + n * footprint;
  local = cluster_local(c, pushed);
  r = length(local);
  if (local.z <= 0.0) return 1.0;
  vec3 direction = (pushed - centre) / r;
  vec2 texel_point = (ssvp_paraboloid_point(local / r) * 0.5 + 0.5) * float(ssvp.paraboloid_size) - 0.5;
  ivec2 corner = ivec2(floor(texel_point));
  vec2 f = texel_point - vec2(corner);
  float visibility = 0.0;
  for (int i = 0; i < 4; ++i) {
    ivec2 offset = ivec2(i & 1, i >> 1);
    ivec2 texel = clamp(corner + offset, ivec2(0), ivec2(ssvp.paraboloid_size - 1));
    float weight = (offset.x == 1 ? f.x : 1.0 - f.x) * (offset.y == 1 ? f.y : 1.0 - f.y);
    if (in_front_of_texel(ivec3(texel, c), centre, direction, r, n, 0.5 * footprint, edge_on_tolerance))
      visibility += weight;
  }
  return visibility;
}

// The VPL's light at the pixel, as the output counts it (x `weight`): `marked` for the second bounce's VPLs.
vec3 vpl_light(Vpl vpl, vec3 x, vec3 n, float weight, uint pixel, bool marked) {
  vec3 e = vpl_irradiance(vpl, x, n) * weight;
  if (e == vec3(0.0)) return e;
  float visibility = cluster_visibility(int(vpl.position_cluster.w), x, n);
  if (settings.ssvp_ray_checks > 0.0 &&
      ray_check_drawn(vpl.position_cluster.xyz, pixel, ssvp.check_random ^ (marked ? 0x9e3779b9u : 0u),
                      settings.ssvp_ray_checks))
    append_ray_check(vpl.position_cluster.xyz, vpl.normal.xyz, visibility, x, n, e, pixel, marked);
  return e * visibility;
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
  uint pixel_index = uint(pixel.y * ssvp.image_width + pixel.x);
  float weight = float(share) / SSVP_PI;
  vec3 first = vec3(0.0), second = vec3(0.0);
  for (int i = start; i < ssvp.first_count; i += share) first += vpl_light(first_vpls[i], x, n, weight, pixel_index, false);
  if (ssvp.bounces > 1)
    for (int i = start; i < ssvp.second_count; i += share)
      second += vpl_light(second_vpls[i], x, n, weight, pixel_index, true);
  out_indirect = vec4(first + second, 0.0);
  out_second = vec4(second, 0.0);
}
