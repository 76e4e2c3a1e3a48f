// Splatting, geometry stage: for each lit side of a VPL, a screen-space quad bounding the support of its
// level's partition function (Eq. 13-16), the ball {d(t_i, x) <= D_{k+1}}: centre y + n D / 2, radius D / 2.
// The last level reaches everywhere and covers the whole view. With interleaved sampling the VPL shades one
// of the 4^level sub-images only, picked by its random (Sec. 6), and the quad is drawn into that sub-image.
#include "flc/flc_common.glsl"
#include "topology_visibility/visibility.glsl"

layout(points) in;
layout(triangle_strip, max_vertices = 8) out;

flat in uint v_vpl[];

flat out vec3 s_vpl_position;
flat out vec3 s_vpl_normal;
flat out vec3 s_radiance_factor;  // rho_i E / pi, times S_k and the interleaving weight
flat out vec4 s_partition;  // D_{k-1}, D_k, D_{k+1}, and (k == 0) + 2 (k == N)
flat out ivec2 s_tile;
flat out uint s_cluster;  // Indirect Shadows: the visibility cluster on the lit side
flat out uint s_ray_map;  // Indirect Shadows: 1 + the lit side's ray map (FlcPass::trace_ray_maps), 0 for none

layout(location = 0) uniform mat4 u_view_projection;

// The ball's bounds in image pixels, or the whole image when it reaches behind the camera.
bool ball_pixel_bounds(vec3 centre, float radius, out vec4 bounds) {
  vec2 lo = vec2(1e30), hi = vec2(-1e30);
  for (int i = 0; i < 8; ++i) {
    vec3 corner = centre + radius * vec3((i & 1) != 0 ? 1.0 : -1.0, (i & 2) != 0 ? 1.0 : -1.0,
                                         (i & 4) != 0 ? 1.0 : -1.0);
    vec4 clip = u_view_projection * vec4(corner, 1.0);
    if (clip.w <= 1e-6 * abs(clip.z) || clip.w <= 0.0) {
      bounds = vec4(0.0, 0.0, flc.image_width, flc.image_height);
      return true;
    }
    vec2 ndc = clip.xy / clip.w;
    lo = min(lo, ndc);
    hi = max(hi, ndc);
  }
  vec2 size = vec2(flc.image_width, flc.image_height);
  lo = max((lo * 0.5 + 0.5) * size - 1.0, vec2(0.0));
  hi = min((hi * 0.5 + 0.5) * size + 1.0, size);
  bounds = vec4(lo, hi);
  return all(lessThan(lo, hi));
}

void emit_side(Vpl vpl, vec3 n, vec4 irradiance_map, ivec2 tile, float tile_weight) {
  vec3 irradiance = irradiance_map.rgb;
  if (all(lessThanEqual(irradiance, vec3(0.0)))) return;
  int level = int(vpl.normal_level.w);
  float support = flc_support_distance(level, flc.levels, flc.d0, flc.mu);
  vec4 bounds = vec4(0.0, 0.0, flc.image_width, flc.image_height);
  if (support >= 0.0 && !ball_pixel_bounds(vpl.position_scale.xyz + 0.5 * support * n, 0.5 * support, bounds))
    return;
  // Image pixels of this sub-image are tile + tiles_per_axis * (local pixel); quad corners in local pixels.
  float t = float(flc.tiles_per_axis);
  vec2 lo = floor((bounds.xy - vec2(tile)) / t);
  vec2 hi = ceil((bounds.zw - vec2(tile)) / t) + 1.0;
  vec2 tile_size = vec2(flc.tile_width, flc.tile_height);
  lo = clamp(lo, vec2(0.0), tile_size);
  hi = clamp(hi, vec2(0.0), tile_size);
  if (any(greaterThanEqual(lo, hi))) return;
  vec2 target = t * tile_size;  // the tiled target holds tiles_per_axis^2 sub-images side by side
  vec2 origin = vec2(tile) * tile_size;
  s_vpl_position = vpl.position_scale.xyz;
  s_vpl_normal = n;
  s_radiance_factor = vpl.albedo_random.rgb * irradiance / FLC_PI * vpl.position_scale.w * tile_weight;
  s_partition = vec4(level > 0 ? flc_level_distance(flc.d0, flc.mu, level - 1) : 0.0,
                     flc_level_distance(flc.d0, flc.mu, level),
                     level < flc.levels ? flc_level_distance(flc.d0, flc.mu, level + 1) : 0.0,
                     float((level == 0 ? 1 : 0) + (level == flc.levels ? 2 : 0)));
  s_tile = tile;
  s_ray_map = flc.visibility != 0 ? floatBitsToUint(irradiance_map.w) : 0u;
  s_cluster = flc.visibility != 0 ? topology_cluster_at(vpl.position_scale.xyz, n) : TOPOLOGY_NO_CLUSTER;
  for (int i = 0; i < 4; ++i) {
    vec2 corner = vec2((i & 1) != 0 ? hi.x : lo.x, (i & 2) != 0 ? hi.y : lo.y);
    gl_Position = vec4((origin + corner) / target * 2.0 - 1.0, 0.0, 1.0);
    EmitVertex();
  }
  EndPrimitive();
}

void main() {
  Vpl vpl = vpls[v_vpl[0]];
  uint random = floatBitsToUint(vpl.albedo_random.w);
  int tiles = flc.tiles_per_axis;
  uint tile_index = pcg_hash(random ^ 0x5bd1e995u) % uint(tiles * tiles);
  ivec2 tile = ivec2(int(tile_index) % tiles, int(tile_index) / tiles);
  // Each VPL reaches one sub-image in tiles^2, chosen uniformly: weighting it by tiles^2 keeps every pixel's
  // expectation.
  float tile_weight = float(tiles * tiles);
  vec3 n = vpl.normal_level.xyz;
  emit_side(vpl, n, vpl.front, tile, tile_weight);
  emit_side(vpl, -n, vpl.back, tile, tile_weight);
}
