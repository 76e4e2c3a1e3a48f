// Direct diffuse light of one light, added into the Direct target: albedo / pi * E * visibility.
#include "common/lights.glsl"

layout(binding = 1) uniform sampler2D g_albedo;
layout(binding = 2) uniform sampler2D g_normal;
layout(binding = 3) uniform sampler2D g_position;
layout(binding = 5) uniform sampler2D g_geometric_normal;
layout(binding = 6) uniform sampler2DShadow shadow_map_2d;
layout(binding = 7) uniform samplerCubeShadow shadow_map_cube;

layout(location = 0) out vec4 out_direct;

// Receiver offset along the geometric normal, in shadow-map texels at the receiver (normal-offset shadows).
vec3 shadow_receiver(vec3 x, vec3 geometric, vec3 to_light) {
  if (dot(geometric, to_light) < 0.0) geometric = -geometric;
  int kind = int(light.shadow_params.x);
  float texel = light.shadow_params.y;
  if (kind != SHADOW_ORTHOGRAPHIC) texel *= length(x - light.shadow_origin.xyz);
  return x + geometric * (settings.shadow_bias * texel);
}

float shadow_visibility(vec3 x, vec3 geometric) {
  int kind = int(light.shadow_params.x);
  if (kind == SHADOW_NONE) return 1.0;
  vec3 to_light = kind == SHADOW_ORTHOGRAPHIC ? light.shadow_origin.xyz : normalize(light.shadow_origin.xyz - x);
  vec3 p = shadow_receiver(x, geometric, to_light);
  if (kind == SHADOW_CUBE) {
    vec3 d = p - light.shadow_origin.xyz;
    float major = max(abs(d.x), max(abs(d.y), abs(d.z)));
    float n = light.shadow_params.z, f = light.shadow_params.w;
    float ndc = (f + n) / (f - n) - 2.0 * f * n / ((f - n) * major);
    return texture(shadow_map_cube, vec4(d, ndc * 0.5 + 0.5));
  }
  vec4 clip = light.shadow_view_projection * vec4(p, 1.0);
  vec3 ndc = clip.xyz / clip.w;
  if (clip.w <= 0.0 || any(greaterThan(abs(ndc.xy), vec2(1.0)))) return kind == SHADOW_ORTHOGRAPHIC ? 1.0 : 0.0;
  return texture(shadow_map_2d, vec3(ndc.xy * 0.5 + 0.5, min(ndc.z * 0.5 + 0.5, 1.0)));
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 albedo = texelFetch(g_albedo, pixel, 0);
  if (albedo.a == 0.0) discard;
  vec3 x = texelFetch(g_position, pixel, 0).xyz;
  vec3 n = texelFetch(g_normal, pixel, 0).xyz;
  vec3 irradiance = light_irradiance(x, n);
  if (all(equal(irradiance, vec3(0.0)))) discard;
  float visibility = shadow_visibility(x, texelFetch(g_geometric_normal, pixel, 0).xyz);
  out_direct = vec4(albedo.rgb / PI * irradiance * visibility, 0.0);
}
