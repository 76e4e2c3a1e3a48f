// One sample's AOVs (Combined = direct + indirect + emission), added into the accumulation targets (depth: kept
// at its minimum by a MIN blend). Indirect light arrives reflected (FLC) or as irradiance / pi, to be
// multiplied by the albedo here (SSVP, which blurs before the albedo so textures stay sharp), and the near field's
// irradiance / pi (near_field/near_field.frag, and near_field_second.frag's second bounce) is added to it times
// the albedo.
#include "common/equirect_shared.glsl"

layout(binding = 1) uniform sampler2D g_albedo;
layout(binding = 2) uniform sampler2D g_normal;
layout(binding = 3) uniform sampler2D g_position;
layout(binding = 4) uniform sampler2D g_emission;
layout(binding = 8) uniform sampler2D direct_light;
layout(binding = 11) uniform sampler2D indirect_light;
layout(binding = 12) uniform sampler2D vpls;

layout(binding = 13) uniform sampler2D environment;
layout(binding = 14) uniform sampler2D near_field;
layout(binding = 15) uniform sampler2D near_field_second;

layout(location = 0) uniform vec3 u_background;  // 0 where the camera does not see the world (transparent, hidden)
layout(location = 1) uniform float u_background_alpha;
layout(location = 2) uniform int u_has_indirect;
layout(location = 3) uniform int u_indirect_times_albedo;
layout(location = 4) uniform int u_has_environment;
layout(location = 5) uniform mat3 u_world_to_environment;
layout(location = 6) uniform mat4 u_clip_to_world;  // of this tile, jittered
layout(location = 7) uniform vec2 u_tile_size;
layout(location = 8) uniform int u_has_near_field;
layout(location = 9) uniform int u_has_near_field_second;

layout(location = 0) out vec4 out_combined;
layout(location = 1) out vec4 out_direct;
layout(location = 2) out vec4 out_emission;
layout(location = 3) out vec4 out_albedo;
layout(location = 4) out vec4 out_normal;
layout(location = 5) out vec4 out_depth;
layout(location = 6) out vec4 out_indirect;
layout(location = 7) out vec4 out_vpls;

const float BACKGROUND_DEPTH = 1e10;  // Blender's Depth pass value where nothing is hit

// The world's radiance toward the view ray of this pixel (bounce.h, BounceWorld; native/src/scene_lights.cpp).
vec3 world_radiance() {
  if (u_has_environment == 0) return u_background;
  vec2 ndc = gl_FragCoord.xy / u_tile_size * 2.0 - 1.0;
  vec4 near = u_clip_to_world * vec4(ndc, -1.0, 1.0);
  vec4 far = u_clip_to_world * vec4(ndc, 1.0, 1.0);
  vec3 e = normalize(u_world_to_environment * (far.xyz / far.w - near.xyz / near.w));
  // Level 0: the seam at u = 0 has no derivative.
  return u_background * textureLod(environment, equirect_uv(e), 0.0).rgb;
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 albedo = texelFetch(g_albedo, pixel, 0);
  out_vpls = u_has_indirect != 0 ? vec4(texelFetch(vpls, pixel, 0).rgb, 0.0) : vec4(0.0);
  if (albedo.a == 0.0) {
    out_combined = vec4(world_radiance(), u_background_alpha);
    out_direct = out_emission = out_albedo = out_normal = out_indirect = vec4(0.0);
    out_depth = vec4(BACKGROUND_DEPTH);
    return;
  }
  vec3 direct = texelFetch(direct_light, pixel, 0).rgb;
  vec3 emission = texelFetch(g_emission, pixel, 0).rgb;
  vec3 indirect = u_has_indirect != 0 ? texelFetch(indirect_light, pixel, 0).rgb : vec3(0.0);
  if (u_indirect_times_albedo != 0) indirect *= albedo.rgb;
  if (u_has_near_field != 0) indirect += albedo.rgb * texelFetch(near_field, pixel, 0).rgb;
  if (u_has_near_field_second != 0) indirect += albedo.rgb * texelFetch(near_field_second, pixel, 0).rgb;
  out_combined = vec4(direct + indirect + emission, 1.0);
  out_indirect = vec4(indirect, 0.0);
  out_direct = vec4(direct, 0.0);
  out_emission = vec4(emission, 0.0);
  out_albedo = vec4(albedo.rgb, 0.0);
  out_normal = vec4(texelFetch(g_normal, pixel, 0).xyz, 0.0);
  out_depth = vec4(texelFetch(g_position, pixel, 0).w);
}
