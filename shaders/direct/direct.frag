// Direct diffuse light of one light, added into the Direct target: albedo / pi * E * visibility.
#include "shadows/shadow_lookup.glsl"

layout(binding = 1) uniform sampler2D g_albedo;
layout(binding = 2) uniform sampler2D g_normal;
layout(binding = 3) uniform sampler2D g_position;
layout(binding = 5) uniform sampler2D g_geometric_normal;
layout(location = 0) uniform ivec2 u_tile_origin;  // so per-pixel noise does not depend on the tiling

layout(location = 0) out vec4 out_direct;

// Receiver offset along the geometric normal, in shadow-map texels at the receiver (normal-offset shadows).
vec3 shadow_receiver(vec3 x, vec3 geometric, vec3 to_light) {
  if (dot(geometric, to_light) < 0.0) geometric = -geometric;
  int kind = int(light.shadow_params.x);
  float texel = light.shadow_params.y;
  if (kind != SHADOW_ORTHOGRAPHIC) texel *= length(x - light.shadow_origin.xyz);
  return x + geometric * (settings.shadow_bias * texel);
}

// The visibility estimate of this sample. Light samples below the receiver's horizon cannot reach it and carry
// no information: visibility counts samples above it only, divided by the probability of landing there, so
// the average over samples is the visibility of the part of the light the receiver sees (unbiased), and a
// receiver whose plane cuts the light is not darkened by the part behind it. Sample 0 is the light's centre,
// not a random point: when that is below the horizon it counts as visible (a bias of at most 1/samples).
float shadow_visibility(vec3 x, vec3 n, vec3 geometric, float above_horizon) {
  int kind = shadow_kind();
  if (kind == SHADOW_NONE) return 1.0;
  vec3 to_light = kind == SHADOW_ORTHOGRAPHIC ? light.shadow_origin.xyz : normalize(light.shadow_origin.xyz - x);
  bool random_sample = light.shadow_soft.z != 0.0;
  if (kind != SHADOW_ORTHOGRAPHIC && above_horizon < 1.0 && random_sample) {
    if (dot(n, to_light) <= 0.0) return 0.0;
  } else {
    above_horizon = 1.0;
  }
  if (dot(n, to_light) <= 0.0) return 1.0;  // the centre, below the horizon
  float cos_theta = max(abs(dot(geometric, to_light)), 0.1);
  float slope = sqrt(1.0 - cos_theta * cos_theta) / cos_theta;
  ivec2 pixel = ivec2(gl_FragCoord.xy) + u_tile_origin;
  uint pixel_hash = uint(pixel.x) * 73856093u ^ uint(pixel.y) * 19349663u ^ floatBitsToUint(light.shadow_soft.z);
  return shadow_visibility_at(shadow_receiver(x, geometric, to_light), slope, pixel_hash) / max(above_horizon, 1e-3);
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 albedo = texelFetch(g_albedo, pixel, 0);
  if (albedo.a == 0.0) discard;
  vec3 x = texelFetch(g_position, pixel, 0).xyz;
  vec3 n = texelFetch(g_normal, pixel, 0).xyz;
  float above_horizon;
  vec3 irradiance = light_irradiance(x, n, above_horizon);
  if (all(equal(irradiance, vec3(0.0)))) discard;
  float visibility = shadow_visibility(x, n, texelFetch(g_geometric_normal, pixel, 0).xyz, above_horizon);
  out_direct = vec4(albedo.rgb / PI * irradiance * visibility, 0.0);
}
