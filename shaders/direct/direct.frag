// Direct diffuse light of one light, added into the Direct target: albedo / pi * E * visibility.
#include "shadows/shadow_lookup.glsl"

layout(binding = 1) uniform sampler2D g_albedo;
layout(binding = 2) uniform sampler2D g_normal;
layout(binding = 3) uniform sampler2D g_position;
layout(binding = 5) uniform sampler2D g_geometric_normal;
layout(location = 0) uniform ivec2 u_tile_origin;  // so per-pixel noise does not depend on the tiling

layout(location = 0) out vec4 out_direct;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 albedo = texelFetch(g_albedo, pixel, 0);
  if (albedo.a == 0.0) discard;
  vec3 x = texelFetch(g_position, pixel, 0).xyz;
  vec3 n = texelFetch(g_normal, pixel, 0).xyz;
  float above_horizon;
  vec3 irradiance = light_irradiance(x, n, above_horizon);
  if (all(equal(irradiance, vec3(0.0)))) discard;
  ivec2 image_pixel = pixel + u_tile_origin;
  uint pixel_hash = uint(image_pixel.x) * 73856093u ^ uint(image_pixel.y) * 19349663u;
  float visibility =
      shadow_visibility(x, n, texelFetch(g_geometric_normal, pixel, 0).xyz, above_horizon, pixel_hash, true);
  out_direct = vec4(albedo.rgb / PI * irradiance * visibility, 0.0);
}
