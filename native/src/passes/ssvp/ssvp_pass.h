// Screen-Space VPL Propagation (Aranha et al. 2020): one or two diffuse bounces of every light.
// Shaders: shaders/ssvp/. Per sample (Fig. 1), for the lights drawn by their flux (ssvp::draw_bouncing_lights):
//   rsm          - each light's reflective shadow map (Sec. II-A, Dachsbacher and Stamminger 2005): the
//                  G-buffer program drawn from the light's views (passes/light_views.h, as its shadow map). Sun:
//                  orthographic over the scene's bounding sphere; spot up to 75 degrees: one perspective face over
//                  its cone; point, area and wider spots: the six faces of a cube around the light's centre, in a
//                  3x2 atlas (the back face of an area light stays empty), which covers all they emit. Kept while
//                  the light and the geometry are unchanged.
//   sample       - first-bounce VPLs at the texels of a 2-D Hammersley set (Eq. 1) per light, of its share of
//                  the VPLs, each carrying its texel's reflected flux: albedo x irradiance x the surface area the
//                  texel sees, times texels / VPLs.
//                  With VPL Importance (not in the paper), 8 times as many candidates, of which the VPLs kept
//                  are resampled on the CPU in proportion to the light they give the surfaces that camera rays
//                  through an 8 x 8 grid over the view meet, shadow rays included (Embree; as the Topology
//                  method draws its VPLs: cpu/vpls.h).
//   cluster      - the VPLs are read back and clustered on the CPU by k-means under Eq. 2 (as intended: see
//                  shaders/ssvp/ssvp_shared.glsl), seeded with the previous frame's clusters (Sec. III-C).
//   paraboloids  - per cluster, a paraboloid map of a hemisphere (Heidrich and Seidel 1998) seen from the
//                  member nearest the cluster's mean (the mean itself may lie inside a solid, Sec. II-B), about
//                  that member's normal and lifted off its surface by 0.1 % of the scene's size, drawn through the
//                  tessellator so that wide triangles bend as they should; each texel's depth is its own
//                  direction's hit on the triangle's plane, so the pieces can stay coarse.
//   propagate    - second-bounce VPLs (Sec. II-B) at uniform unit-disk points of each cluster's map, each
//                  carrying albedo x the cluster's intensity towards it (its members' cosine lobes) x the solid
//                  angle its disk area covers (the map's Jacobian, 4 / (1 + r^2)^2).
//   second       - not in the paper. With VPL Importance, the second-bounce VPLs are traced instead (Embree:
//                  cosine rays from the first-bounce candidates, the hits kept by importance as the first
//                  bounce's are; see trace_second_bounce). Either way they are read back and clustered as the
//                  first-bounce VPLs are, each cluster with its own paraboloid map after the first bounce's.
//   shade        - interleaved (Sec. II-C): the pixels of each tile take one share of the VPLs each. A
//                  first-bounce VPL is shadowed by its own cluster's paraboloid map (clustered visibility, Dong
//                  et al. 2009); a second-bounce VPL by its own second-bounce cluster's map. Then the
//                  geometry-aware blur recombines the pixels. Output: linear irradiance / pi of each bounce;
//                  the compose pass multiplies the albedo (no tone mapping: Blender's colour management does the
//                  display transform).
//   debug        - VPLs and cluster centres drawn in cluster colours over the G-buffer's depth.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "cpu/cpu_scene.h"
#include "cpu/view_probes.h"
#include "cpu/vpls.h"
#include "gl/objects.h"
#include "passes/blur/geometry_blur.h"
#include "passes/gbuffer/gbuffer_pass.h"
#include "passes/ray_checks/ray_checks.h"
#include "passes/render_context.h"
#include "passes/ssvp/ssvp_math.h"
#include "scene_lights.h"

namespace bounce {

// std140 mirror of shaders/ssvp/ssvp_common.glsl `SsvpParams`.
struct SsvpParams {
  float light_origin[4];  // xyz: the RSM's eye (sun: the direction towards the light), w: RSM kind
  int32_t first_count, second_count, cluster_count, tiles_per_axis;
  int32_t rsm_face_size, rsm_faces_x, rsm_faces_y, paraboloid_size;
  float rsm_texel_factor;  // sun: the texel's side in world units; perspective: 2 tan(half fov) / size
  float texels_per_vpl;    // RSM texels / this light's first-bounce VPLs
  float epsilon;           // distance clamp in world units
  float length_scale;      // the scene's diameter (Eq. 2)
  float w1, w2, paraboloid_far;
  int32_t second_per_cluster, bounces, pattern_rotation;
  int32_t first_offset;         // while sampling: where this light's VPLs start (first_count: how many)
  float texels_per_capped_vpl;  // RSM texels / all the sample's first-bounce VPLs: the area that caps them
  int32_t image_width;          // while shading: the tile's
  uint32_t check_random;        // while shading: which pairs Ray Checks draws, new every sample
};

class SsvpPass {
 public:
  struct GpuVpl;  // std430 mirror of shaders/ssvp/ssvp_common.glsl `Vpl` (ssvp_pass.cpp)

  SsvpPass();
  // Once per sample, for the whole view (`context` covers every tile): the light's RSM, the VPLs, their
  // clusters and paraboloid maps, the second bounce. `traced`: Embree's copy of the scene when the frame plan
  // draws the VPLs by importance, else null. `sample_lights`: the sample's list of lights (the context's), whose lamps
  // keep their places from sample to sample.
  void generate(const RenderContext& context, const GBufferPass& gbuffers, const cpu::CpuScene* traced,
                const SceneLights& sample_lights);
  // Per tile: the pixels of `camera` lit by the sample's VPLs, blurred; the debug view.
  void shade(const RenderContext& context, const GBuffer& camera, const std::optional<RayCheckSettings>& checks);

  bool active() const { return first_count_ + second_count_ > 0; }
  GLuint indirect() const { return total_; }    // RGBA32F irradiance / pi, both bounces
  GLuint second() const { return second_; }     // RGBA32F irradiance / pi, the second bounce alone (0: off)
  GLuint debug() const { return debug_.id(); }  // RGBA16F
  uint32_t vpl_count() const { return first_count_ + second_count_; }
  uint32_t cluster_count() const { return static_cast<uint32_t>(clusters_.size()); }
  // Index in the sample's lights of the one drawn most often to bounce.
  int main_light() const { return main_light_; }
  // The sample's first-bounce candidates, capped by their areas as the shading pass caps the VPLs: they estimate
  // the first bounce where the near field's rays meet a surface no pixel sees (cpu::UnseenFirstBounce). Not the
  // VPLs kept by importance, which are drawn by the light they give what the camera sees.
  std::span<const cpu::Vpl> first_bounce_candidates() const { return first_bounce_candidates_; }

 private:
  struct Rsm {
    GBuffer gbuffer;
    BounceLight light{};
    uint64_t geometry_version = 0;
    int face_size = 0, faces_x = 0, faces_y = 0, kind = 0;  // kind: LightViewKind
    glm::vec3 origin{0.0f};
    float texel_factor = 0.0f;
  };

  // The RSM of `light` (unweighted): a slot's kept one when it is of the same light and geometry, else drawn into
  // a slot that no light of this sample has claimed yet.
  const Rsm& render_rsm(const RenderContext& context, const GBufferPass& gbuffers, const BounceLight& light,
                        std::vector<bool>& claimed);
  void prepare_candidates(const RenderContext& context, uint32_t count);
  // The candidates [offset, offset + count) from `rsm`, of `light` weighted by its draws.
  void sample_first_bounce(const RenderContext& context, const Rsm& rsm, const BounceLight& light,
                           cpu::EmissionGuide* guide, uint32_t offset, uint32_t count);
  // Returns the second-bounce VPLs when it traces them (VPL Importance), else none. `probes` weigh the candidates
  // and check the clusters' eyes; `fine_probes` weigh the candidates that reach none of them.
  std::vector<GpuVpl> cluster(const RenderContext& context, const cpu::CpuScene* traced,
                              std::span<const cpu::ViewProbe> probes, std::span<const cpu::ViewProbe> fine_probes);
  void allocate_paraboloids(const RenderContext& context, int layers);
  void render_paraboloids(const RenderContext& context, int begin, int end);  // layers [begin, end)
  void propagate(const RenderContext& context);
  std::vector<GpuVpl> read_propagated();
  void cluster_second_bounce(const RenderContext& context, std::vector<GpuVpl> vpls, const cpu::CpuScene* traced,
                             std::span<const cpu::ViewProbe> probes);
  void shade_vpls(const RenderContext& context, const GBuffer& camera, const std::optional<RayCheckSettings>& checks);
  void draw_debug(const RenderContext& context, const GBuffer& camera);

  gl::Program sample_program_, paraboloid_program_, propagate_program_, shade_program_, debug_program_;
  GeometryBlur blur_total_, blur_second_;
  RayChecks ray_checks_;  // applied to the shaded light, before the blur
  gl::Buffer params_buffer_, light_buffer_, points_, first_vpls_, clusters_buffer_, second_vpls_;
  gl::Readback first_vpls_readback_, second_vpls_readback_;
  std::size_t points_capacity_ = 0, first_capacity_ = 0, clusters_capacity_ = 0, second_capacity_ = 0;
  SsvpParams params_{};
  std::vector<Rsm> rsms_;  // one per light drawn in a sample, kept for the next

  gl::Texture paraboloid_position_, paraboloid_normal_, paraboloid_albedo_, paraboloid_depth_;
  gl::Framebuffer paraboloid_target_;
  int paraboloid_layers_ = 0, paraboloid_size_ = 0;

  gl::Texture shaded_total_, shaded_second_, debug_;
  gl::Framebuffer shade_target_, debug_target_;
  GLuint debug_depth_ = 0;
  int width_ = 0, height_ = 0;
  GLuint total_ = 0, second_ = 0;

  std::vector<glm::vec2> disk_points_;
  // Where the first-bounce candidates fall on each lamp's RSM (with VPL Importance): learned over a render's
  // samples from the candidates' importance, as the Topology method guides its lamps' emission (cpu/vpls.h).
  std::vector<cpu::EmissionGuide> guides_;
  std::vector<glm::vec2> candidate_points_;            // this sample's, over their light's RSM atlas
  std::vector<float> candidate_weights_;               // 1 / the guide's density there
  std::vector<cpu::EmissionGuide*> candidate_guides_;  // their light's guide (null: none)
  std::vector<cpu::EmissionGuide*> sample_guides_;     // the guides of this sample's lights
  std::vector<cpu::Vpl> first_bounce_candidates_;
  std::vector<ssvp::Cluster> clusters_, previous_clusters_;
  std::vector<ssvp::Cluster> second_clusters_, previous_second_clusters_;  // their maps follow the first's
  uint32_t first_count_ = 0, second_count_ = 0;
  int first_wanted_ = 0,
      second_wanted_ = 0;  // first-bounce VPLs kept; the sample pass makes more candidates with VPL Importance
  int main_light_ = -1;
  float max_tess_level_ = 64.0f;
};

}  // namespace bounce
