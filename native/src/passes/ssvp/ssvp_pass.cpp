#include "passes/ssvp/ssvp_pass.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

#include <glm/gtc/type_ptr.hpp>

#include "common/parallel.h"
#include "cpu/camera_ray.h"
#include "cpu/vpls.h"
#include "error.h"
#include "gl/shader.h"
#include "passes/direct/direct_pass.h"
#include "passes/light_views.h"
#include "sampling.h"

namespace bounce {

namespace {

constexpr GLuint kParamsBlock = 5;
constexpr GLuint kPointsBinding = 6;
constexpr GLuint kFirstBinding = 7;
constexpr GLuint kClustersBinding = 8;
constexpr GLuint kSecondBinding = 9;
constexpr GLuint kParaboloidPositionUnit = 13;
constexpr GLuint kParaboloidNormalUnit = 14;
constexpr GLuint kParaboloidAlbedoUnit = 15;
constexpr int kMinSecondPerCluster = 32;  // Sec. III-D
constexpr float kCentreLift = 1e-3f;      // a paraboloid map's eye off its surface, per unit of scene size
constexpr double kParaboloidMemoryBudget = 512.0 * 1024.0 * 1024.0;
// The light's G-buffer holds each face at the RSM size: a point light's six faces at the largest RSM Size (4096)
// took 5.2 GB (issue 18 measured a 5.4 GiB peak), so the size halves until they fit, as shadow maps do.
constexpr double kRsmMemoryBudget = 1024.0 * 1024.0 * 1024.0;
constexpr int kParaboloidBytesPerTexel = 16 + 8 + 8 + 4;

struct GpuVpl {
  glm::vec4 position_cluster, normal, flux;
};
struct GpuCluster {
  glm::vec4 position_first, normal_count, tangent, bitangent;
};

struct Probe {
  glm::vec3 position, normal, albedo;
};

// VPL Importance's view samples: the surface a camera ray meets through one jittered point in each cell of a
// grid over the whole view (all the tiles of a tiled frame share them), as the rasterizer sees it (cut-outs let
// the ray through).
std::vector<Probe> camera_probes(const RenderContext& frame, const cpu::CpuScene& scene, uint32_t seed) {
  std::vector<Probe> probes;
  const glm::dmat4 clip_to_world = glm::inverse(glm::dmat4(frame.view_projection));
  const int cells = cpu::kProbesPerAxis;
  for (int cell = 0; cell < cells * cells; ++cell) {
    const uint32_t key = hash_combine(seed, static_cast<uint32_t>(cell));
    const double x = (cell % cells + hash_to_unit(key)) / cells,
                 y = (cell / cells + hash_to_unit(key ^ 0x9e37u)) / cells;
    const cpu::CameraRay ray = cpu::camera_ray(clip_to_world, 2.0 * x - 1.0, 2.0 * y - 1.0);
    if (!std::isfinite(ray.direction.x) || !std::isfinite(ray.origin.x)) continue;
    const std::optional<embree::Hit> hit = scene.intersect(ray.origin, ray.direction, 0.0f, ray.tmax);
    if (!hit) continue;
    const cpu::Surface surface = scene.surface(*hit, ray.direction);
    probes.push_back({surface.position, surface.shading_normal, surface.albedo});
  }
  return probes;
}

// Resampled importance (Talbot et al. 2005; cpu::resample): a candidate's importance is the light it gives the
// probes, each behind a shadow ray, so the VPLs kept go where their light reaches what the camera sees. A kept
// VPL's flux grows by its draw's weight and its area does not: the light it gives is then its candidate's
// (capped by vpl_irradiance in ssvp_common.glsl at the candidate's exitance) times the weight. Unlike the
// Topology method's, the draw has no defensive share: a candidate that reaches no probe is left out. Kept, it
// would carry m / (share x count) times a VPL's flux (80 times), and clustered visibility, which tests it from
// its cluster's eye, lets it through walls: a sunlit room came out 2-3 times too bright. Left out, only light
// that no probe sees is lost; the probes move every sample.
std::vector<GpuVpl> draw_by_importance(std::span<const GpuVpl> candidates, int wanted, std::span<const Probe> probes,
                                       const cpu::CpuScene& scene, float clamp, float u) {
  const float offset = scene.ray_offset();
  std::vector<float> importance(candidates.size(), 0.0f);
  parallel_for(candidates.size(), 0, 16, [&](std::size_t i) {
    const cpu::Vpl vpl{glm::vec3(candidates[i].position_cluster), glm::vec3(candidates[i].normal),
                       glm::vec3(candidates[i].flux)};
    double sum = 0.0;
    for (const Probe& probe : probes) {
      const glm::vec3 light = probe.albedo * cpu::vpl_irradiance(vpl, probe.position, probe.normal, clamp);
      if (!(light.r + light.g + light.b > 0.0f)) continue;
      if (!scene.clear_between(vpl.position + vpl.normal * offset, probe.position + probe.normal * offset)) continue;
      sum += double(light.r + light.g + light.b);
    }
    importance[i] = float(sum);
  });
  // When no candidate reaches a probe (a room the main light's first bounce cannot enter), none is kept: the
  // same rule, where cpu::resample would fall back to drawing them all alike.
  std::vector<GpuVpl> kept;
  if (std::none_of(importance.begin(), importance.end(), [](float value) { return value > 0.0f; })) return kept;
  for (const cpu::Draw& draw : cpu::resample(importance, wanted, /*uniform_share=*/0.0f, u)) {
    GpuVpl vpl = candidates[draw.index];
    vpl.flux = glm::vec4(glm::vec3(vpl.flux) * draw.weight, vpl.flux.w);
    kept.push_back(vpl);
  }
  return kept;
}

// Clustered visibility tests a member's light from its cluster's eye, so a member that cannot see that eye (on the
// other side of a wall) lights what the eye sees, through the wall. Such a member joins the cluster nearest it
// under Eq. 2 whose eye it sees (Embree shadow rays); one that sees no eye stays.
void keep_eyes_in_sight(std::span<const ssvp::ClusterPoint> points, std::span<const ssvp::Cluster> clusters,
                        std::span<const glm::vec3> eyes, const ssvp::ClusterMetric& metric, const cpu::CpuScene& scene,
                        std::vector<uint32_t>& assignment) {
  const float offset = scene.ray_offset();
  const auto sees = [&](std::size_t i, std::size_t c) {
    return scene.clear_between(points[i].position + points[i].normal * offset, eyes[c]);
  };
  parallel_for(points.size(), 0, 16, [&](std::size_t i) {
    if (sees(i, assignment[i])) return;
    std::vector<std::pair<float, uint32_t>> others;
    for (uint32_t c = 0; c < eyes.size(); ++c)
      if (c != assignment[i])
        others.emplace_back(ssvp::ssvp_cluster_distance(points[i].position, points[i].normal, clusters[c].position,
                                                        clusters[c].normal, metric.w1, metric.w2, metric.length_scale),
                            c);
    std::sort(others.begin(), others.end());
    for (const auto& [distance, c] : others)
      if (sees(i, c)) {
        assignment[i] = c;
        return;
      }
  });
}

}  // namespace

SsvpPass::SsvpPass()
    : sample_program_(gl::build_program({{GL_COMPUTE_SHADER, "ssvp/ssvp_sample.comp"}})),
      paraboloid_program_(gl::build_program({{GL_VERTEX_SHADER, "gbuffer/gbuffer.vert"},
                                             {GL_TESS_CONTROL_SHADER, "ssvp/ssvp_paraboloid.tesc"},
                                             {GL_TESS_EVALUATION_SHADER, "ssvp/ssvp_paraboloid.tese"},
                                             {GL_FRAGMENT_SHADER, "ssvp/ssvp_paraboloid.frag"}})),
      propagate_program_(gl::build_program({{GL_COMPUTE_SHADER, "ssvp/ssvp_propagate.comp"}})),
      shade_program_(gl::build_program(
          {{GL_VERTEX_SHADER, "common/fullscreen.vert"}, {GL_FRAGMENT_SHADER, "ssvp/ssvp_shade.frag"}})),
      debug_program_(gl::build_program(
          {{GL_VERTEX_SHADER, "ssvp/ssvp_debug.vert"}, {GL_FRAGMENT_SHADER, "common/flat_colour.frag"}})),
      params_buffer_(gl::make_buffer(sizeof(SsvpParams), nullptr)),
      light_buffer_(gl::make_buffer(sizeof(LightBlock), nullptr)) {
  GLint max_tess_level = 64;
  glGetIntegerv(GL_MAX_TESS_GEN_LEVEL, &max_tess_level);
  max_tess_level_ = static_cast<float>(max_tess_level);
  gl::check("creating the SSVP pass");
}

void SsvpPass::generate(const RenderContext& context, const GBufferPass& gbuffers, const cpu::CpuScene* traced) {
  first_count_ = second_count_ = 0;
  main_light_ = -1;
  clusters_.clear();
  const glm::vec3 lo = context.scene.bounds_min(), hi = context.scene.bounds_max();
  const float scene_radius = 0.5f * glm::length(hi - lo);
  if (!context.scene.has_geometry() || !(scene_radius > 0.0f) || !std::isfinite(scene_radius)) return;
  const auto& lights = context.lights;
  // Sample 0 draws with no rotation, as it keeps one Hammersley set: a still scene gives the same frame again.
  const float rotation = context.sample == 0 ? 0.0f : hash_to_unit(hash_combine(context.seed, 0x5355u));
  const ssvp::LightDraw draw = ssvp::draw_bouncing_light(lights, 0.5f * (lo + hi), scene_radius,
                                                         r2_point(context.sample, glm::vec2(rotation)).x);
  main_light_ = draw.index;
  if (main_light_ < 0) return;
  BounceLight light = lights[static_cast<std::size_t>(main_light_)];
  for (float& c : light.intensity) c /= draw.probability;
  const BounceSettings& s = context.settings;

  SsvpParams& p = params_;
  p = {};
  if (traced && traced->triangle_count() == 0) traced = nullptr;  // nothing to trace: the paper's VPLs
  first_wanted_ = std::clamp(s.ssvp_vpls, 1, 1 << 16);
  p.first_count = traced ? first_wanted_ * cpu::kCandidatesPerVpl : first_wanted_;
  p.tiles_per_axis = 1 << std::clamp(s.ssvp_tiling, 0, 4);
  p.epsilon = s.ssvp_distance_clamp * scene_radius;
  p.length_scale = 2.0f * scene_radius;
  p.w1 = s.ssvp_position_weight;
  p.w2 = s.ssvp_normal_weight;
  p.paraboloid_far = 2.2f * p.length_scale;
  p.bounces = std::clamp(s.bounces, 1, 2);
  // Sample 0 keeps one pattern, as it keeps one Hammersley set: a still scene gives the same frame again.
  p.pattern_rotation =
      context.sample == 0 ? 0 : static_cast<int32_t>(hash_combine(context.seed, context.sample) % 65536u);

  render_rsm(context, gbuffers, light);
  sample_first_bounce(context, light);
  cluster(context, traced);
  if (clusters_.empty()) {
    first_count_ = 0;
    return;
  }
  render_paraboloids(context);
  if (p.bounces > 1) propagate(context);
}

void SsvpPass::shade(const RenderContext& context, const GBuffer& camera) {
  if (!active()) return;
  shade_vpls(context, camera);
  draw_debug(context, camera);
}

void SsvpPass::render_rsm(const RenderContext& context, const GBufferPass& gbuffers, const BounceLight& light) {
  const LightViewKind kind = light_view_kind(light);
  // A cube's faces sit in a 3 x 2 atlas, so one Hammersley set over the atlas samples all of them.
  const int faces_x = kind == kLightViewCube ? 3 : 1, faces_y = kind == kLightViewCube ? 2 : 1;
  const int size = size_within_budget(std::clamp(context.settings.ssvp_rsm_size, 16, 8192), 64, faces_x * faces_y,
                                      kGBufferBytesPerTexel, kRsmMemoryBudget);
  const bool reuse = rsm_.gbuffer.width == faces_x * size && rsm_.gbuffer.height == faces_y * size &&
                     rsm_.geometry_version == context.scene.geometry_version() &&
                     std::memcmp(&rsm_.light, &light, sizeof light) == 0;
  if (!reuse) {
    StageScope scope(context.timer, Stage::SsvpRsm);
    if (rsm_.gbuffer.width != faces_x * size || rsm_.gbuffer.height != faces_y * size)
      rsm_.gbuffer = make_gbuffer(faces_x * size, faces_y * size);
    const glm::vec3 origin =
        kind == kLightViewOrthographic ? glm::normalize(vec3_of(light.axis_z)) : vec3_of(light.position);
    const LightViews views = light_views(light, origin, context.scene.bounds_min(), context.scene.bounds_max(), size);
    std::vector<GBufferView> faces;
    for (int f = 0; f < views.faces; ++f) {
      if (f == views.skipped_face) continue;
      const glm::vec3 forward = -glm::vec3(glm::transpose(views.view[f])[2]);
      faces.push_back({views.view_projection[f],
                       views.view[f],
                       origin,
                       forward,
                       kind == kLightViewOrthographic,
                       {(f % 3) * size, (f / 3) * size, size, size}});
    }
    gbuffers.render(rsm_.gbuffer, faces, context.scene);
    rsm_.light = light;
    rsm_.geometry_version = context.scene.geometry_version();
    rsm_.face_size = size;
    rsm_.faces_x = faces_x;
    rsm_.faces_y = faces_y;
    rsm_.kind = kind;
    rsm_.origin = origin;
    rsm_.texel_factor = views.texel_factor;
    gl::check("rendering the reflective shadow map");
  }
  params_.light_origin[0] = rsm_.origin.x;
  params_.light_origin[1] = rsm_.origin.y;
  params_.light_origin[2] = rsm_.origin.z;
  params_.light_origin[3] = static_cast<float>(rsm_.kind);
  params_.rsm_face_size = rsm_.face_size;
  params_.rsm_faces_x = rsm_.faces_x;
  params_.rsm_faces_y = rsm_.faces_y;
  params_.rsm_texel_factor = rsm_.texel_factor;
}

void SsvpPass::sample_first_bounce(const RenderContext& context, const BounceLight& light) {
  StageScope scope(context.timer, Stage::SsvpCluster);
  SsvpParams& p = params_;
  const uint32_t n = static_cast<uint32_t>(p.first_count);
  p.texels_per_vpl = static_cast<float>(double(rsm_.gbuffer.width) * rsm_.gbuffer.height / n);
  // Sample 0 samples the same VPLs every frame (Sec. III-C); later samples rotate the set over the RSM.
  const glm::vec2 rotation =
      context.sample == 0 ? glm::vec2(0.0f)
                          : r2_point(context.sample, glm::vec2(hash_to_unit(hash_combine(context.seed, 0x5353u)),
                                                               hash_to_unit(hash_combine(context.seed, 0x5354u))));
  // The second bounce's disk points follow the first-bounce points in the same buffer, once cluster() knows
  // how many of those found a surface.
  const int clusters_wanted = std::clamp(context.settings.ssvp_clusters, 1, 256);
  p.second_per_cluster =
      std::max(kMinSecondPerCluster,
               (std::clamp(context.settings.ssvp_second_vpls, 1, 1 << 16) + clusters_wanted - 1) / clusters_wanted);
  disk_points_ = ssvp::disk_set(static_cast<uint32_t>(p.second_per_cluster), glm::vec2(rotation.y, rotation.x));
  const std::vector<glm::vec2> points = ssvp::hammersley_set(n, rotation);
  gl::reserve_buffer(points_, points_capacity_, (points.size() + disk_points_.size()) * sizeof(glm::vec2));
  glNamedBufferSubData(points_.id(), 0, static_cast<GLsizeiptr>(points.size() * sizeof(glm::vec2)), points.data());
  gl::reserve_buffer(first_vpls_, first_capacity_, n * sizeof(GpuVpl));
  glNamedBufferSubData(params_buffer_.id(), 0, sizeof p, &p);

  LightBlock block = make_light_block(light);
  glNamedBufferSubData(light_buffer_.id(), 0, sizeof block, &block);
  glBindBufferBase(GL_UNIFORM_BUFFER, binding::kLightBlock, light_buffer_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, kParamsBlock, params_buffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kPointsBinding, points_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kFirstBinding, first_vpls_.id());
  rsm_.gbuffer.bind_for_reading();
  glUseProgram(sample_program_.id());
  gl::dispatch_linear(n, 64);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
  gl::check("sampling the first-bounce VPLs");
}

void SsvpPass::cluster(const RenderContext& context, const cpu::CpuScene* traced) {
  SsvpParams& p = params_;
  std::vector<GpuVpl> vpls;
  {
    StageScope scope(context.timer, Stage::SsvpCluster);
    std::vector<GpuVpl> sampled(static_cast<std::size_t>(p.first_count));
    first_vpls_readback_.read(first_vpls_.id(), sampled.size() * sizeof(GpuVpl), sampled.data());
    for (const GpuVpl& v : sampled)
      if (v.flux.w != 0.0f && v.flux.r + v.flux.g + v.flux.b > 0.0f) vpls.push_back(v);
  }
  if (traced) {
    StageScope scope(context.timer, Stage::SsvpImportance);
    const uint32_t key = hash_combine(context.seed, context.sample ^ 0x494d5054u);
    vpls = draw_by_importance(vpls, first_wanted_, camera_probes(context, *traced, key), *traced, p.epsilon,
                              hash_to_unit(hash_combine(key, 1u)));
  }
  StageScope scope(context.timer, Stage::SsvpCluster);
  std::vector<ssvp::ClusterPoint> points;
  for (const GpuVpl& v : vpls) points.push_back({glm::vec3(v.position_cluster), glm::vec3(v.normal)});
  const ssvp::ClusterMetric metric{p.w1, p.w2, p.length_scale};
  const std::span<const ssvp::Cluster> seeds = context.settings.ssvp_temporal_seeding
                                                   ? std::span<const ssvp::Cluster>(previous_clusters_)
                                                   : std::span<const ssvp::Cluster>();
  ssvp::Clustering clustering =
      ssvp::cluster_points(points, context.settings.ssvp_clusters, metric, seeds, hash_combine(context.seed, 0x4b4du));
  clusters_ = clustering.clusters;
  if (clusters_.empty()) return;
  previous_clusters_ = clusters_;

  // The paper's prototype sits at the members' mean (Sec. II-B), which it warns "may appear as floating in
  // space": the mean of VPLs on a floor and on a block's top lies inside the block, and a paraboloid map seen
  // from there hides everything, dimming the whole cluster's light. The map's eye is instead the member nearest
  // that mean, a point on a lit surface, lifted off it along its own normal, which is also the map's axis: about
  // the members' mean normal, the eye's own surface would rise above the map's horizon and, seen at grazing
  // angles, hide the receivers on it (a third of a wall's light in Ssvp.ParaboloidEyeOnALitSurface).
  std::vector<std::size_t> eye_member(clusters_.size(), points.size());
  std::vector<float> eye_distance(clusters_.size(), std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const uint32_t c = clustering.assignment[i];
    const glm::vec3 d = points[i].position - clusters_[c].position;
    if (glm::dot(d, d) < eye_distance[c]) eye_distance[c] = glm::dot(d, d), eye_member[c] = i;
  }
  std::vector<glm::vec3> eyes(clusters_.size());
  for (std::size_t c = 0; c < clusters_.size(); ++c)
    eyes[c] = points[eye_member[c]].position + points[eye_member[c]].normal * (kCentreLift * p.length_scale);
  std::vector<uint32_t> assignment = clustering.assignment;
  if (traced) keep_eyes_in_sight(points, clusters_, eyes, metric, *traced, assignment);

  // Members sorted by cluster, so a cluster's members are a range (the propagation sums over them); the
  // interleaved shading takes every T^2-th VPL of this order, which spreads every cluster over the tiles.
  std::vector<uint32_t> order(vpls.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return assignment[a] < assignment[b]; });
  for (ssvp::Cluster& cluster : clusters_) cluster.count = 0;
  for (uint32_t c : assignment) ++clusters_[c].count;
  std::vector<GpuVpl> sorted(vpls.size());
  std::vector<GpuCluster> gpu_clusters(clusters_.size());
  uint32_t first = 0;
  for (std::size_t c = 0; c < clusters_.size(); ++c) {
    const glm::vec3 axis = points[eye_member[c]].normal, tangent = any_perpendicular(axis);
    gpu_clusters[c] = {glm::vec4(eyes[c], static_cast<float>(first)),
                       glm::vec4(axis, static_cast<float>(clusters_[c].count)), glm::vec4(tangent, 0.0f),
                       glm::vec4(glm::cross(axis, tangent), 0.0f)};
    first += clusters_[c].count;
  }
  for (std::size_t i = 0; i < order.size(); ++i) {
    sorted[i] = vpls[order[i]];
    sorted[i].position_cluster.w = static_cast<float>(assignment[order[i]]);
  }
  first_count_ = static_cast<uint32_t>(sorted.size());
  p.first_count = static_cast<int32_t>(first_count_);
  p.cluster_count = static_cast<int32_t>(clusters_.size());
  p.second_count = p.bounces > 1 ? p.cluster_count * p.second_per_cluster : 0;
  second_count_ = static_cast<uint32_t>(p.second_count);
  // The shaders find the disk points right after the `first_count` first-bounce points.
  glNamedBufferSubData(points_.id(), static_cast<GLintptr>(first_count_ * sizeof(glm::vec2)),
                       static_cast<GLsizeiptr>(disk_points_.size() * sizeof(glm::vec2)), disk_points_.data());
  gl::upload_buffer(first_vpls_, first_capacity_, sorted.size() * sizeof(GpuVpl), sorted.data());
  gl::upload_buffer(clusters_buffer_, clusters_capacity_, gpu_clusters.size() * sizeof(GpuCluster),
                    gpu_clusters.data());
  gl::reserve_buffer(second_vpls_, second_capacity_, second_count_ * sizeof(GpuVpl));
  glNamedBufferSubData(params_buffer_.id(), 0, sizeof p, &p);
  gl::check("clustering the first-bounce VPLs");
}

void SsvpPass::render_paraboloids(const RenderContext& context) {
  StageScope scope(context.timer, Stage::SsvpParaboloids);
  const int layers = static_cast<int>(clusters_.size());
  const int size = size_within_budget(std::clamp(context.settings.ssvp_paraboloid_size, 16, 4096), 16, layers,
                                      kParaboloidBytesPerTexel, kParaboloidMemoryBudget);
  if (layers > paraboloid_layers_ || size != paraboloid_size_) {
    const int allocated = std::max(layers, paraboloid_layers_);
    auto make_array = [&](GLenum format) {
      GLuint id = 0;
      glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &id);
      glTextureStorage3D(id, 1, format, size, size, allocated);
      glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      return gl::Texture(id);
    };
    paraboloid_position_ = make_array(GL_RGBA32F);
    paraboloid_normal_ = make_array(GL_RGBA16F);
    paraboloid_albedo_ = make_array(GL_RGBA16F);
    paraboloid_depth_ = make_array(GL_DEPTH_COMPONENT32F);
    GLuint framebuffer = 0;
    glCreateFramebuffers(1, &framebuffer);
    paraboloid_target_ = gl::Framebuffer(framebuffer);
    const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glNamedFramebufferDrawBuffers(framebuffer, 3, buffers);
    paraboloid_layers_ = allocated;
    paraboloid_size_ = size;
    gl::check("allocating the paraboloid maps");
  }
  params_.paraboloid_size = size;
  glNamedBufferSubData(params_buffer_.id(), 0, sizeof params_, &params_);
  glBindBufferBase(GL_UNIFORM_BUFFER, kParamsBlock, params_buffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kClustersBinding, clusters_buffer_.id());
  const GLuint target = paraboloid_target_.id();
  glBindFramebuffer(GL_FRAMEBUFFER, target);
  glViewport(0, 0, size, size);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_CLIP_DISTANCE0);
  glPatchParameteri(GL_PATCH_VERTICES, 3);
  glUseProgram(paraboloid_program_.id());
  glUniform1f(11, max_tess_level_);
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  const float far_depth = 1.0f;
  for (int c = 0; c < layers; ++c) {
    glNamedFramebufferTextureLayer(target, GL_COLOR_ATTACHMENT0, paraboloid_position_.id(), 0, c);
    glNamedFramebufferTextureLayer(target, GL_COLOR_ATTACHMENT1, paraboloid_normal_.id(), 0, c);
    glNamedFramebufferTextureLayer(target, GL_COLOR_ATTACHMENT2, paraboloid_albedo_.id(), 0, c);
    glNamedFramebufferTextureLayer(target, GL_DEPTH_ATTACHMENT, paraboloid_depth_.id(), 0, c);
    for (int i = 0; i < 3; ++i) glClearBufferfv(GL_COLOR, i, zero);
    glClearBufferfv(GL_DEPTH, 0, &far_depth);
    glUniform1i(10, c);
    context.scene.draw(GL_PATCHES);
  }
  glDisable(GL_CLIP_DISTANCE0);
  glDisable(GL_DEPTH_TEST);
  gl::check("rendering the paraboloid maps");
}

void SsvpPass::propagate(const RenderContext& context) {
  StageScope scope(context.timer, Stage::SsvpCluster);
  glBindBufferBase(GL_UNIFORM_BUFFER, kParamsBlock, params_buffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kPointsBinding, points_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kFirstBinding, first_vpls_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kClustersBinding, clusters_buffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kSecondBinding, second_vpls_.id());
  glBindTextureUnit(kParaboloidPositionUnit, paraboloid_position_.id());
  glBindTextureUnit(kParaboloidNormalUnit, paraboloid_normal_.id());
  glBindTextureUnit(kParaboloidAlbedoUnit, paraboloid_albedo_.id());
  glUseProgram(propagate_program_.id());
  gl::dispatch_linear(second_count_, 64);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  gl::check("propagating the second-bounce VPLs");
}

void SsvpPass::shade_vpls(const RenderContext& context, const GBuffer& camera) {
  if (width_ != context.width || height_ != context.height) {
    shaded_total_ = gl::make_texture_2d(GL_RGBA32F, context.width, context.height);
    shaded_second_ = gl::make_texture_2d(GL_RGBA32F, context.width, context.height);
    shade_target_ = gl::make_framebuffer({shaded_total_.id(), shaded_second_.id()}, 0);
    debug_ = gl::make_texture_2d(GL_RGBA16F, context.width, context.height);
    debug_depth_ = 0;
    width_ = context.width;
    height_ = context.height;
    gl::check("allocating the SSVP targets");
  }
  {
    StageScope scope(context.timer, Stage::SsvpShade);
    glBindFramebuffer(GL_FRAMEBUFFER, shade_target_.id());
    glViewport(0, 0, width_, height_);
    camera.bind_for_reading();
    glBindBufferBase(GL_UNIFORM_BUFFER, kParamsBlock, params_buffer_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kFirstBinding, first_vpls_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kClustersBinding, clusters_buffer_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kSecondBinding, second_vpls_.id());
    glBindTextureUnit(kParaboloidPositionUnit, paraboloid_position_.id());
    glUseProgram(shade_program_.id());
    draw_fullscreen_triangle();
  }
  StageScope scope(context.timer, Stage::SsvpDenoise);
  const int radius = context.settings.ssvp_blur_radius;
  total_ = blur_total_.run(shaded_total_.id(), camera, radius);
  second_ = params_.bounces > 1 ? blur_second_.run(shaded_second_.id(), camera, radius) : 0;
}

void SsvpPass::draw_debug(const RenderContext& context, const GBuffer& camera) {
  StageScope scope(context.timer, Stage::SsvpShade);
  if (debug_depth_ != camera.depth.id()) {
    debug_target_ = gl::make_framebuffer({debug_.id()}, camera.depth.id());
    debug_depth_ = camera.depth.id();
  }
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  glClearNamedFramebufferfv(debug_target_.id(), GL_COLOR, 0, zero);
  glBindFramebuffer(GL_FRAMEBUFFER, debug_target_.id());
  glViewport(0, 0, width_, height_);
  glUseProgram(debug_program_.id());
  glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(context.view_projection));
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDepthMask(GL_FALSE);
  glEnable(GL_PROGRAM_POINT_SIZE);
  glBindVertexArray(empty_vertex_array());
  const GLsizei counts[3] = {static_cast<GLsizei>(first_count_), static_cast<GLsizei>(second_count_),
                             static_cast<GLsizei>(clusters_.size())};
  for (int kind = 0; kind < 3; ++kind) {
    glUniform1i(1, kind);
    if (counts[kind] > 0) glDrawArrays(GL_POINTS, 0, counts[kind]);
  }
  glBindVertexArray(0);
  glDisable(GL_PROGRAM_POINT_SIZE);
  glDepthMask(GL_TRUE);
  glDisable(GL_DEPTH_TEST);
  gl::check("drawing the SSVP debug view");
}

}  // namespace bounce
