// The direct irradiance E(t_i) of Eq. 6 at every VPL, from the light bound in LightBlock with its shadow map,
// added for each light in turn. Both sides of the (two-sided) triangle are lit separately.
#include "flc/flc_common.glsl"
#include "shadows/shadow_lookup.glsl"

layout(local_size_x = 64) in;
#include "common/dispatch.glsl"

layout(location = 0) uniform uint u_vpl_count;

vec3 side_irradiance(vec3 y, vec3 n, uint decorrelation) {
  float above_horizon;
  vec3 irradiance = light_irradiance(y, n, above_horizon);
  if (all(equal(irradiance, vec3(0.0)))) return vec3(0.0);
  // Unfiltered: E(t_i) averages over the samples' light points anyway, and the filter's margin leaks light onto
  // grazing VPLs (Sponza: FLC's mean indirect 1.35x its CPU model filtered, 1.26x unfiltered).
  return irradiance * shadow_visibility(y, n, n, above_horizon, decorrelation, false);
}

void main() {
  uint index = linear_invocation();
  if (index >= u_vpl_count) return;
  vec3 y = vpls[index].position_scale.xyz;
  vec3 n = vpls[index].normal_level.xyz;
  uint random = floatBitsToUint(vpls[index].albedo_random.w);
  vpls[index].front.rgb += side_irradiance(y, n, random);
  vpls[index].back.rgb += side_irradiance(y, -n, random);
}
