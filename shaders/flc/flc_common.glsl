// Forward Light Cuts buffers and parameters (mirrors: native/src/passes/flc/flc_pass.cpp).
#include "common/random.glsl"
#include "flc/flc_shared.glsl"

const float FLC_PI = 3.14159265358979;

layout(std140, binding = 5) uniform FlcParams {
  float s0;                    // S_0 (Eq. 1)
  float mu;                    // Eq. 17
  float epsilon;               // distance clamp of Eq. 5, metres
  float inverse_cumulative_n;  // 1 / S-bar_N: triangles larger than S-bar_N are divergent
  int levels;                  // N
  int tiles_per_axis;          // 2^tiling level
  int jitter;
  int divergent;
  uint u_rand;                 // Alg. 2, new every sample
  uint vpl_capacity;
  uint divergent_capacity;
  float max_tess_level;
  int image_width, image_height;  // of the tile being rendered (the G-buffer)
  int tile_width, tile_height;    // of one interleaved sub-image
  float scene_radius;
  float d0;                    // D_0 = D_near (Eq. 1, 18)
  int visibility;              // 1: Indirect Shadows (shaders/topology_visibility/visibility.glsl)
  int cosine_lobe;             // 1: Eq. 6's radiance, in proportion to the cosine at the light; 0: Lambertian
  float draw_mu;               // the level ratio Alg. 1 draws with (mu, or sqrt(mu) for candidates)
} flc;

// One virtual point light: a triangle that survived Alg. 1, its point y_i and level k, and the direct
// irradiance E(t_i) on each side, summed over the lights by flc_light.comp.
struct Vpl {
  vec4 position_scale;  // y_i, and the splat weight F^k / f^k = S_k (times the oversize weight; a candidate's own)
  vec4 normal_level;    // geometric normal n_i, level k
  vec4 albedo_random;   // rho_i, the triangle's random number (bits)
  vec4 front;           // E on the side n_i faces
  vec4 back;            // E on the other side
};

// A divergent triangle (area above S-bar_N) waiting for the tessellator, in world space. Its albedo is the
// base colour filtered over the whole triangle (the paper fetches from an atlas; here the mip level that
// covers it), so one indirect draw serves every material.
struct DivergentTriangle {
  vec4 p0_random;  // position, per-vertex random (bits)
  vec4 p1_random;
  vec4 p2_random;
  vec4 albedo_instance;  // rho, the instance's random (bits)
};

// Indirect draw commands (glDrawArraysIndirect) whose counts the generating shaders bump.
layout(std430, binding = 6) coherent buffer FlcCounters {
  uint vpl_draw[4];        // count, instances, first, base instance: the VPLs as points
  uint divergent_draw[4];  // the divergent triangles as instances of one 3-vertex patch (flc_divergent.vert)
  uint vpl_overflow;
  uint divergent_overflow;
};
layout(std430, binding = 7) buffer Vpls { Vpl vpls[]; };
layout(std430, binding = 8) buffer Divergents { DivergentTriangle divergents[]; };

#ifdef BOUNCE_GEOMETRY_SHADER
// Appends a VPL for a triangle with level `level`; `scale` is S_k times the oversize weight.
void flc_store_vpl(vec3 y, vec3 n, int level, float scale, vec3 albedo, uint random) {
  uint index = atomicAdd(vpl_draw[0], 1u);
  if (index >= flc.vpl_capacity) {
    // Give the slot back so the count stays the number written; the host grows the buffer and redoes the
    // sample.
    atomicAdd(vpl_draw[0], uint(-1));
    atomicAdd(vpl_overflow, 1u);
    return;
  }
  vpls[index].position_scale = vec4(y, scale);
  vpls[index].normal_level = vec4(n, float(level));
  vpls[index].albedo_random = vec4(albedo, uintBitsToFloat(random));
  vpls[index].front = vec4(0.0);
  vpls[index].back = vec4(0.0);
}

// Alg. 1 for one triangle (p0, p1, p2) of area `area` and random `random`; returns its level (-1: discarded)
// and writes the barycentric weights of its VPL's point: the centroid, or a uniform point when jittering
// (progressive rendering, Sec. 6).
int flc_choose(float area, float weight, uint random, out vec3 barycentric) {
  int level = flc_level(flc_unit(random), area / weight, flc.s0, flc.draw_mu, flc.levels);
  barycentric = flc.jitter != 0 ? flc_triangle_point(flc_unit(pcg_hash(random ^ 0x68bc21ebu)),
                                                     flc_unit(pcg_hash(random ^ 0x02e5be93u)))
                                : vec3(1.0 / 3.0);
  return level;
}
#endif
