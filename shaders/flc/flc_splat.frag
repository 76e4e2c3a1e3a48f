// Splatting, fragment stage: the VPL's contribution H(t_i, x, n_x) F^k(t_i, x) to the receiver of this pixel
// (Eq. 5, 6, 10, 14, 16), added into the interleaved indirect target; with Indirect Shadows, as much as the
// topology's clusters, gates and passages let the VPL reach the pixel; never across an emitter
// (emitter_occluders.glsl).
#include "common/emitter_occluders.glsl"
#include "flc/flc_common.glsl"
#include "ray_checks/ray_checks.glsl"
#include "topology_visibility/visibility.glsl"

layout(binding = 1) uniform sampler2D g_albedo;
layout(binding = 2) uniform sampler2D g_normal;
layout(binding = 3) uniform sampler2D g_position;

flat in vec3 s_vpl_position;
flat in vec3 s_vpl_normal;
flat in vec3 s_radiance_factor;
flat in vec4 s_partition;
flat in ivec2 s_tile;
flat in uint s_cluster;
flat in uint s_ray_map;

layout(binding = 21) uniform usampler2D pixel_clusters;  // TopologyVisibilityPass::kPixelClustersUnit
// Per ray map, per bin the visibility cluster its ray enters (TOPOLOGY_NO_CLUSTER for none) and the distance to the
// surface it meets, as float bits (FlcPass::trace_ray_maps).
layout(std430, binding = 15) readonly buffer FlcRayMaps { uvec2 flc_ray_maps[]; };

layout(location = 0) out vec4 out_indirect;

void main() {
  ivec2 local = ivec2(gl_FragCoord.xy) - s_tile * ivec2(flc.tile_width, flc.tile_height);
  ivec2 pixel = local * flc.tiles_per_axis + s_tile;
  if (any(greaterThanEqual(pixel, ivec2(flc.image_width, flc.image_height)))) discard;
  // Most fragments of a quad lie outside the VPL's support: the position alone decides, before the other
  // fetches.
  vec3 x = texelFetch(g_position, pixel, 0).xyz;
  vec3 to_receiver = x - s_vpl_position;
  float distance2 = dot(to_receiver, to_receiver);
  if (!(distance2 > 0.0)) discard;
  float distance = sqrt(distance2);
  vec3 direction = to_receiver / distance;
  float cos_emitter = dot(s_vpl_normal, direction);
  if (cos_emitter <= 0.0) discard;
  int ends = int(s_partition.w);
  float f = flc_partition_between(distance / cos_emitter, s_partition.x, s_partition.y, s_partition.z,
                                  (ends & 1) != 0, (ends & 2) != 0);  // Eq. 14, 16
  if (f == 0.0) discard;
  vec4 albedo = texelFetch(g_albedo, pixel, 0);
  if (albedo.a == 0.0) discard;
  vec3 normal = texelFetch(g_normal, pixel, 0).xyz;
  float cos_receiver = -dot(normal, direction);
  if (cos_receiver <= 0.0) discard;
  if (emitter_between(s_vpl_position, x, 1e-4 * flc.scene_radius)) discard;
  // A light in thin geometry (a ray map) reaches the empty space through the cluster its ray of the receiver's bin
  // enters, and on from there as the topology lets it, the surfaces around the receiver hiding it only where that
  // ray entered the empty space (the ray saw to the thin geometry itself: the slats above a slat's sunlit top hid
  // its light twice, 0.88 of the shadow rays'). Where the ray meets a surface first, it reaches a receiver about as
  // far (the wall behind a ledge) as the topology lets light of the cluster it fell back on: the ray alone lit the
  // other side of a thin wall beside it. One call of topology_visibility: llvmpipe took three times as long to splat
  // with a second.
  uint from = s_cluster;
  float reach = TOPOLOGY_WITHIN_CLUSTER;
  if (s_ray_map != 0u) {
    uvec2 bin = flc_ray_maps[(s_ray_map - 1u) * uint(FLC_RAY_MAP_BINS) +
                             uint(octahedral_bin(direction, FLC_RAY_MAP_BINS_PER_SIDE))];
    float along = uintBitsToFloat(bin.y);
    from = bin.x != TOPOLOGY_NO_CLUSTER ? bin.x
           : flc_ray_map_reaches(along, distance) ? s_cluster
                                                  : TOPOLOGY_NO_CLUSTER;
    if (bin.x != TOPOLOGY_NO_CLUSTER) reach = max(distance - along, 0.0);
  }
  float visibility = flc.visibility != 0 ? topology_visibility(from, s_vpl_position, s_vpl_normal,
                                                               texelFetch(pixel_clusters, pixel, 0).r, x, normal, reach)
                                         : 1.0;
  // Ray Checks: a random share of the pairs, lit or not by the rule, goes to the CPU, where a shadow ray's verdict
  // corrects the rule's (a control variate: Topology's Ray Checks, cpu::TopologyRenderer).
  uint pixel_index = uint(pixel.y * flc.image_width + pixel.x);
  bool checked = flc.visibility != 0 && settings.flc_ray_checks > 0.0 &&
                 ray_check_drawn(s_vpl_position, pixel_index, flc.u_rand, settings.flc_ray_checks);
  if (visibility == 0.0 && !checked) discard;
  float clamped = max(flc.epsilon, distance);
  // L(t_i, y_i x) = rho_i E / pi, a diffuse surface's; with Cosine-Lobe Lights Eq. 6's rho_i E 3/(2 pi)
  // <n_i, y_i x>+, which leaves light at grazing angles too dark. Eq. 9 holds for either: the partition of Eq. 16
  // over d = |x - y| / <n_i, y_i x> is one of unity whatever the radiance.
  // H = L rho_x <n_x, x y_i>+ <n_i, y_i x>+ / (pi d^2) (Eq. 5).
  float lobe = flc.cosine_lobe != 0 ? 1.5 * cos_emitter : 1.0;
  vec3 h = s_radiance_factor * lobe * albedo.rgb * cos_receiver * cos_emitter / (FLC_PI * clamped * clamped) * f;
  if (checked) append_ray_check(s_vpl_position, s_vpl_normal, visibility, x, normal, h, pixel_index, false);
  out_indirect = vec4(h * visibility, 0.0);
}
