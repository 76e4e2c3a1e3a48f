// Divergent pipeline, geometry stage: each sub-triangle becomes a VPL exactly like a regular triangle
// (Alg. 1), its random from the base triangle's and the sub-vertices' noise (Alg. 2).
#include "flc/flc_common.glsl"

layout(triangles) in;
layout(points, max_vertices = 1) out;

in vec3 e_position[];
flat in uint e_triangle[];
flat in uint e_noise_random[];

void main() {
  vec3 p0 = e_position[0], p1 = e_position[1], p2 = e_position[2];
  vec3 c = cross(p1 - p0, p2 - p0);
  float twice_area = length(c);
  float area = 0.5 * twice_area;
  if (!(area > 0.0) || isinf(area)) return;
  DivergentTriangle t = divergents[e_triangle[0]];
  uint base_random = floatBitsToUint(t.p0_random.w) ^ floatBitsToUint(t.p1_random.w) ^
                     floatBitsToUint(t.p2_random.w);
  uint random = flc_triangle_random(flc.u_rand, base_random ^ e_noise_random[0], e_noise_random[1],
                                    e_noise_random[2], floatBitsToUint(t.albedo_instance.w));
  float weight = flc_oversize_weight(area, flc.inverse_cumulative_n);
  vec3 barycentric;
  int level = flc_choose(area, weight, random, barycentric);
  if (level < 0) return;
  vec3 y = barycentric.x * p0 + barycentric.y * p1 + barycentric.z * p2;
  flc_store_vpl(y, c / twice_area, level, weight * flc_level_area(flc.s0, flc.draw_mu, level), t.albedo_instance.rgb,
                random);
}
