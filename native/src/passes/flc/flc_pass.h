// Forward Light Cuts (Laurent et al. 2016): the first diffuse bounce from one VPL per surviving triangle.
// Shaders: shaders/flc/. Per sample, once for all tiles (the VPLs do not depend on the view):
//   generate   - regular pipeline: one geometry-shader pass over every triangle (Sec. 4, Alg. 1); divergent
//                triangles are stored on the GPU and drawn again through the tessellator with
//                glDrawArraysIndirect (Sec. 6, Alg. 2). VPLs go to a buffer.
//   add_light  - per light, with its shadow map bound: the direct irradiance E(t_i) at every VPL (Eq. 6);
//   or add_traced_light - every light at once on the CPU, with Embree shadow rays (Shadows > Ray Traced).
// and per tile of the sample:
//   shade      - splatting of every VPL's support (Eq. 5, 10, 14, 16) into 4^L interleaved sub-images, then
//                untiling and a depth- and normal-aware blur; plus the VPL-levels debug view (Fig. 3). With
//                Indirect Shadows, a VPL's splat lights a pixel only where the topology of the empty space lets
//                it (same visibility cluster, or through a gate of its cluster: Noel and Biri 2014, Fig. 11):
//                the paper has no indirect visibility, so light went through walls.
// The paper generates and splats in one geometry shader with one light. Keeping the VPLs in a buffer between
// the stages lets any number of lights (each with its own shadow map) light the same VPLs, and counts them.
#pragma once

#include <cstdint>

#include <optional>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "cpu/cpu_scene.h"
#include "gl/objects.h"
#include "passes/blur/geometry_blur.h"
#include "passes/gbuffer/gbuffer_pass.h"
#include "passes/ray_checks/ray_checks.h"
#include "passes/render_context.h"
#include "passes/topology_visibility/topology_visibility_pass.h"
#include "scene_lights.h"

namespace bounce {

// std140 mirror of shaders/flc/flc_common.glsl `FlcParams`.
struct FlcParams {
  float s0, mu, epsilon, inverse_cumulative_n;
  int32_t levels, tiles_per_axis, jitter, divergent;
  uint32_t u_rand, vpl_capacity, divergent_capacity;
  float max_tess_level;
  int32_t image_width, image_height, tile_width, tile_height;
  float scene_radius;
  float d0;
  int32_t visibility;   // 1: the topology's clusters and gates shadow the VPLs (TopologyVisibilityPass bound)
  int32_t cosine_lobe;  // 1: Eq. 6's radiance, in proportion to the cosine at the light; 0: Lambertian
  float draw_mu;        // the level ratio Alg. 1 draws with: mu, or sqrt(mu) for candidates (FlcPass::generate)
};

// The pass's parameters for one sample: Eq. 1 (S_0 from N_avg and D_near), Eq. 17-18, the interleaving level.
FlcParams make_flc_params(const BounceSettings& settings, float scene_radius, uint32_t seed, uint32_t sample);
// The interleaved sub-images of an image (a tile) `width` x `height` (Sec. 6).
void set_flc_image(FlcParams& params, int width, int height);

class FlcPass {
 public:
  FlcPass();
  // candidates: Alg. 1 draws `candidates` times the VPLs of level 0 and more of the coarser levels, as many within
  // each level's reach D_k; add_traced_light keeps about the paper's number of each level, in proportion to the
  // light each reflects (1: the paper's VPLs, by area alone; needs add_traced_light).
  void generate(const RenderContext& context, int candidates);
  void add_light(const RenderContext& context);
  // E(t_i) from every light of the sample with the visible fraction of each from a shadow ray, as the ray-traced
  // direct light has it (cpu/direct_light.h; `lights` made the sample's list), then the candidates kept. With
  // `visibility` (Indirect Shadows), the lit sides of the kept VPLs that its grid cannot place get ray maps.
  void add_traced_light(const RenderContext& context, const cpu::CpuScene& scene, const SceneLights& lights,
                        const TopologyVisibilityPass* visibility);
  // With `visibility` (Indirect Shadows), each VPL lights only what the topology's clusters and gates let it; with
  // `checks` too (Ray Checks), shadow rays in `checks->scene` correct the rule's verdict on a share of the pairs.
  void shade(const RenderContext& context, const GBuffer& gbuffer, const TopologyVisibilityPass* visibility,
             const std::optional<RayCheckSettings>& checks);

  bool active() const { return vpl_count_ > 0; }
  struct HostVpl {  // std430 mirror of shaders/flc/flc_common.glsl `Vpl`
    glm::vec4 position_scale, normal_level, albedo_random, front, back;
  };
  GLuint indirect() const { return resolved_; }  // RGBA32F, the tile's size
  GLuint levels() const { return levels_.id(); }
  uint32_t vpl_count() const { return vpl_count_; }
  uint32_t divergent_count() const { return divergent_count_; }

 private:
  struct Counters {  // std430 mirror of `FlcCounters`
    uint32_t vpl_draw[4];
    uint32_t divergent_draw[4];
    uint32_t vpl_overflow, divergent_overflow;
  };

  void run_pipelines(const RenderContext& context);
  std::vector<double> view_reach(const RenderContext& context, const cpu::CpuScene& scene) const;
  void trace_ray_maps(const RenderContext& context, const cpu::CpuScene& scene,
                      const TopologyVisibilityPass& visibility);
  void resize(int width, int height, const FlcParams& params);

  gl::Program regular_, divergent_, lighting_, splat_, untile_, levels_program_;
  GeometryBlur blur_;
  gl::Buffer params_buffer_, counters_, vpls_, divergents_;
  gl::Readback counters_readback_, vpls_readback_;
  std::vector<HostVpl> traced_vpls_;  // add_traced_light's copy of the VPLs
  // Per VPL side with a ray map (its front.w or back.w holds 1 + the map's index as float bits, 0 without one):
  // per bin of the octahedral map, the visibility cluster a ray of the bin enters (topology::kNoNode: none).
  std::vector<uint32_t> ray_maps_;
  gl::Buffer ray_maps_buffer_;
  std::size_t ray_maps_capacity_ = 0;  // words
  RayChecks ray_checks_;               // applied to the untiled light, before the blur
  gl::Texture noise_;
  FlcParams params_{};
  float max_tess_level_ = 64.0f;  // GL_MAX_TESS_GEN_LEVEL, queried once
  uint32_t vpl_capacity_ = 0, divergent_capacity_ = 0;
  uint32_t vpl_count_ = 0, divergent_count_ = 0;
  int candidates_ = 1;  // generate()'s

  gl::Framebuffer generation_target_;  // no attachments: the generating draws rasterize nothing
  gl::Texture tiled_, untiled_, levels_;
  gl::Framebuffer tiled_target_, untiled_target_, levels_target_;
  GLuint resolved_ = 0;
  int width_ = 0, height_ = 0, tiled_width_ = 0, tiled_height_ = 0;
  GLuint levels_depth_ = 0;
};

}  // namespace bounce
