// First-bounce VPLs (Sec. II-A) of one bouncing light: one per point of its Hammersley set (Eq. 1), at its
// reflective shadow map's texel under it. Its flux is what that texel's surface reflects: albedo x irradiance x
// the area the texel sees, scaled by texels / VPLs so that the VPLs together carry the whole reflected flux.
#include "common/lights.glsl"
#include "ssvp/ssvp_common.glsl"

layout(local_size_x = 64) in;
#include "common/dispatch.glsl"

layout(binding = 1) uniform sampler2D rsm_albedo;
layout(binding = 2) uniform sampler2D rsm_normal;
layout(binding = 3) uniform sampler2D rsm_position;
layout(binding = 5) uniform sampler2D rsm_geometric_normal;

const float MIN_COSINE = 1e-2;  // grazing texels see a long strip; their area is capped there

void main() {
  if (linear_invocation() >= uint(ssvp.first_count)) return;
  uint k = uint(ssvp.first_offset) + linear_invocation();
  ivec2 atlas = ivec2(ssvp.rsm_faces_x, ssvp.rsm_faces_y) * ssvp.rsm_face_size;
  ivec2 texel = min(ivec2(points[k] * vec2(atlas)), atlas - 1);
  vec4 albedo = texelFetch(rsm_albedo, texel, 0);
  Vpl vpl;
  vpl.position_cluster = vec4(0.0);
  vpl.normal = vec4(0.0, 0.0, 1.0, 0.0);
  vpl.flux = vec4(0.0);
  if (albedo.a > 0.0) {
    vec3 x = texelFetch(rsm_position, texel, 0).xyz;
    vec3 n = texelFetch(rsm_normal, texel, 0).xyz;
    vec3 ng = texelFetch(rsm_geometric_normal, texel, 0).xyz;
    float above_horizon;
    vec3 irradiance = light_irradiance(x, n, above_horizon);
    float area;
    if (int(ssvp.light_origin.w) == RSM_ORTHOGRAPHIC) {
      area = ssvp.rsm_texel_factor * ssvp.rsm_texel_factor / max(dot(ng, ssvp.light_origin.xyz), MIN_COSINE);
    } else {
      // A texel of a perspective face at q (in [-1, 1]^2) spans the solid angle f^2 / (1 + t^2 |q|^2)^(3/2),
      // f = 2t / size, t = tan(half fov).
      vec2 q = (vec2(texel % ssvp.rsm_face_size) + 0.5) / float(ssvp.rsm_face_size) * 2.0 - 1.0;
      float t = 0.5 * ssvp.rsm_texel_factor * float(ssvp.rsm_face_size);
      float solid_angle = ssvp.rsm_texel_factor * ssvp.rsm_texel_factor / pow(1.0 + t * t * dot(q, q), 1.5);
      vec3 to_light = ssvp.light_origin.xyz - x;
      float d2 = dot(to_light, to_light);
      area = solid_angle * d2 / max(dot(ng, to_light * inversesqrt(max(d2, 1e-30))), MIN_COSINE);
    }
    vpl.position_cluster = vec4(x, float(k));  // w: its point, until it joins a cluster (SsvpPass::cluster)
    vpl.normal = vec4(n, area * ssvp.texels_per_capped_vpl);
    vpl.flux = vec4(albedo.rgb * irradiance * area * ssvp.texels_per_vpl, 1.0);
    if (any(isnan(vpl.flux)) || any(isinf(vpl.flux))) vpl.flux = vec4(0.0);
  }
  first_vpls[k] = vpl;
}
