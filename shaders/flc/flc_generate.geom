// Regular pipeline, geometry stage: one pass over every triangle (Sec. 6). Divergent triangles (area above
// S-bar_N) go to the divergent buffer for the tessellator; regular ones are decimated and partitioned by
// Alg. 1 and become one VPL each. Nothing is rasterized.
#include "common/scene.glsl"
#include "flc/flc_common.glsl"

layout(triangles) in;
layout(points, max_vertices = 1) out;

in vec3 v_world_position[];
in vec2 v_uv[];
flat in uint v_random[];
flat in uint v_instance_random[];

// The base colour filtered over a footprint of `uv_area` (in uv units squared) around uv; alpha is the
// coverage of a cut-out.
vec4 filtered_base_color(vec2 uv, float uv_area) {
  vec2 size = vec2(textureSize(u_base_color_texture, 0));
  float lod = 0.5 * log2(max(uv_area * size.x * size.y, 1.0));
  Material m = materials[u_material];
  vec4 texel = textureLod(u_base_color_texture, uv, lod);
  float alpha = m.flags.y != 0 ? m.base_color_alpha.a * texel.a : m.base_color_alpha.a;
  return vec4(m.base_color_alpha.rgb * texel.rgb, alpha);
}

float uv_triangle_area() {
  vec2 a = v_uv[1] - v_uv[0], b = v_uv[2] - v_uv[0];
  return 0.5 * abs(a.x * b.y - a.y * b.x);
}

void main() {
  vec3 p0 = v_world_position[0], p1 = v_world_position[1], p2 = v_world_position[2];
  vec3 c = cross(p1 - p0, p2 - p0);
  float twice_area = length(c);
  float area = 0.5 * twice_area;
  if (!(area > 0.0) || isinf(area)) return;  // degenerate after the instance transform, or NaN
  bool cut_out_material = materials[u_material].flags.y != 0;

  if (area * flc.inverse_cumulative_n > 1.0) {
    if (flc.divergent == 0) return;
    vec4 base = filtered_base_color((v_uv[0] + v_uv[1] + v_uv[2]) / 3.0, uv_triangle_area());
    // Cut-outs: the filtered alpha is the covered fraction, so it scales the reflected light.
    vec3 albedo = cut_out_material ? base.rgb * base.a : base.rgb;
    uint index = atomicAdd(divergent_draw[1], 1u);
    if (index >= flc.divergent_capacity) {
      atomicAdd(divergent_draw[1], uint(-1));
      atomicAdd(divergent_overflow, 1u);
      return;
    }
    divergents[index].p0_random = vec4(p0, uintBitsToFloat(v_random[0]));
    divergents[index].p1_random = vec4(p1, uintBitsToFloat(v_random[1]));
    divergents[index].p2_random = vec4(p2, uintBitsToFloat(v_random[2]));
    divergents[index].albedo_instance = vec4(albedo, uintBitsToFloat(v_instance_random[0]));
    return;
  }

  uint random = flc_triangle_random(flc.u_rand, v_random[0], v_random[1], v_random[2], v_instance_random[0]);
  vec3 barycentric;
  int level = flc_choose(area, 1.0, random, barycentric);
  if (level < 0) return;
  vec2 uv = barycentric.x * v_uv[0] + barycentric.y * v_uv[1] + barycentric.z * v_uv[2];
  // Jittered lights see the texture at their point (a cut-out hole holds no light); centred ones stand for
  // the whole triangle and see it filtered over it.
  vec4 base = filtered_base_color(uv, flc.jitter != 0 ? 0.0 : uv_triangle_area());
  if (cut_out_material) {
    if (flc.jitter != 0 && surface_is_cut_out(base.a)) return;
    if (flc.jitter == 0) base.rgb *= base.a;
  }
  vec3 y = barycentric.x * p0 + barycentric.y * p1 + barycentric.z * p2;
  flc_store_vpl(y, c / twice_area, level, flc_level_area(flc.s0, flc.draw_mu, level), base.rgb, random);
}
