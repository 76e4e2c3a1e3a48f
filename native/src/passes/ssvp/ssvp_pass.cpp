#include "passes/ssvp/ssvp_pass.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <tuple>

#include <glm/gtc/type_ptr.hpp>

#include "common/parallel.h"
#include "cpu/vpls.h"
#include "error.h"
#include "gl/shader.h"
#include "passes/direct/direct_pass.h"
#include "passes/light_views.h"
#include "radiometry.h"
#include "sampling.h"

namespace bounce {

struct SsvpPass::GpuVpl {
  glm::vec4 position_cluster, normal, flux;
};

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
constexpr float kMinSecondCosine = 1e-2f;  // as MIN_COSINE in ssvp_propagate.comp
// The view samples a candidate that reaches none of the kProbesPerAxis^2 probes is weighed again at
// (candidate_importance). With the coarse ones alone, the boxes on the budget's open ground (a tenth of the view)
// got 0.93 of Cycles' first bounce (0.94 with four times the VPLs, 1.03 with 24 x 24 probes for every candidate).
constexpr int kFineProbesPerAxis = 16;
constexpr uint32_t kRayCheckStream = 41;  // which VPL-pixel pairs Ray Checks draws

using GpuVpl = SsvpPass::GpuVpl;
using Probe = cpu::ViewProbe;
struct GpuCluster {
  glm::vec4 position_first, normal_count, tangent, bitangent;
};

// The VPLs of a GPU buffer that exist (their sample met a surface) and carry light.
std::vector<GpuVpl> read_lit_vpls(gl::Readback& readback, GLuint buffer, std::size_t count) {
  std::vector<GpuVpl> read(count), lit;
  readback.read(buffer, count * sizeof(GpuVpl), read.data());
  for (const GpuVpl& v : read)
    if (v.flux.w != 0.0f && v.flux.r + v.flux.g + v.flux.b > 0.0f) lit.push_back(v);
  return lit;
}

// The rotation of a sample's Hammersley sets over the RSMs and of its disk points. A still scene gives the same
// VPLs for a sample and a seed every frame (Sec. III-C); the seed rotates every sample, the first included, so
// that renders with different seeds are independent estimates.
glm::vec2 sample_rotation(const RenderContext& context) {
  return r2_point(context.sample, glm::vec2(hash_to_unit(hash_combine(context.seed, 0x5353u)),
                                            hash_to_unit(hash_combine(context.seed, 0x5354u))));
}

// The clusters of each bounce (the Clusters setting; the paper uses 4-32), the second's too, also when the first
// bounce keeps no VPL.
int clusters_per_bounce(const BounceSettings& settings) { return std::clamp(settings.ssvp_clusters, 1, 256); }

// The seed of a sample's view samples and of its draws by importance.
uint32_t importance_key(const RenderContext& context) {
  return hash_combine(context.seed, context.sample ^ 0x494d5054u);
}

// Resampled importance (Talbot et al. 2005; cpu::resample): a candidate's importance is the light it gives the
// probes, each behind a shadow ray, so the VPLs kept go where their light reaches what the camera sees. A kept
// VPL's flux grows by its draw's weight and its area does not: the light it gives is then its candidate's
// (capped by vpl_irradiance in ssvp_common.glsl at the candidate's exitance) times the weight. Unlike the
// Topology method's, the draw has no defensive share: a candidate that reaches no probe is left out. Kept, it
// would carry m / (share x count) times a VPL's flux (80 times), and clustered visibility, which tests it from
// its cluster's eye, lets it through walls: a sunlit room came out 2-3 times too bright. Left out, the light that
// reaches only what falls between the probes is lost, so a candidate that reaches none of `probes` is weighed
// again at the denser `fine_probes` (scaled to as many probes): only what falls between those is lost.
std::vector<float> candidate_importance(std::span<const GpuVpl> candidates, std::span<const Probe> probes,
                                        std::span<const Probe> fine_probes, const cpu::CpuScene& scene, float clamp) {
  const float offset = scene.ray_offset();
  std::vector<float> importance(candidates.size(), 0.0f);
  parallel_for(candidates.size(), 0, 16, [&](std::size_t i) {
    const cpu::Vpl vpl{glm::vec3(candidates[i].position_cluster), glm::vec3(candidates[i].normal),
                       glm::vec3(candidates[i].flux)};
    const auto light_at = [&](std::span<const Probe> set) {
      double sum = 0.0;
      for (const Probe& probe : set) {
        const glm::vec3 light = probe.albedo * cpu::vpl_irradiance(vpl, probe.position, probe.normal, clamp);
        if (!(light.r + light.g + light.b > 0.0f)) continue;
        if (!scene.clear_between(vpl.position + vpl.normal * offset, probe.position + probe.normal * offset)) continue;
        sum += double(light.r + light.g + light.b);
      }
      return sum;
    };
    double sum = light_at(probes);
    if (sum == 0.0 && !fine_probes.empty())
      sum = light_at(fine_probes) * double(probes.size()) / double(fine_probes.size());
    importance[i] = float(sum);
  });
  return importance;
}

// A kept VPL carries the flux of 1 / (wanted x its probability) candidates, and stands for their area too, which caps
// the light it gives (vpl_irradiance in ssvp_common.glsl) at its surface's exitance. With the candidate's own area,
// the cap held a VPL drawn often (where the light reaches the view) to a fraction of that exitance and let one drawn
// seldom give several times it: SSVP with Ray Checks, 96x54, 16 samples, seeds 0-2, the open ground's second bounce
// 0.666 -> 0.805 of Cycles', Sponza's 0.894 -> 0.920, the two rooms' first bounce 1.034 -> 0.995 (Indirect relMSE
// 4x4 0.00898 -> 0.00686).
std::vector<GpuVpl> keep_by_importance(std::span<const GpuVpl> candidates, std::span<const float> importance,
                                       int wanted, float u) {
  // When no candidate reaches a probe (a room the main light's first bounce cannot enter), none is kept: the
  // same rule, where cpu::resample would fall back to drawing them all alike.
  std::vector<GpuVpl> kept;
  if (std::none_of(importance.begin(), importance.end(), [](float value) { return value > 0.0f; })) return kept;
  for (const cpu::Draw& draw : cpu::resample(importance, wanted, /*uniform_share=*/0.0f, u)) {
    GpuVpl vpl = candidates[draw.index];
    vpl.flux = glm::vec4(glm::vec3(vpl.flux) * draw.weight, vpl.flux.w);
    vpl.normal.w *= draw.weight;
    kept.push_back(vpl);
  }
  return kept;
}

// Sorts `vpls` by their cluster (stably) and writes `cluster_offset` + the cluster into each one's
// position_cluster.w, its paraboloid map's layer; returns the number of VPLs in each of the `cluster_count`
// clusters. A cluster's VPLs are then a range (the propagation sums over them), and the interleaved shading,
// which takes every T^2-th VPL of this order, spreads every cluster over the tiles.
std::vector<uint32_t> sort_by_cluster(std::vector<GpuVpl>& vpls, std::span<const uint32_t> assignment,
                                      uint32_t cluster_offset, std::size_t cluster_count) {
  std::vector<uint32_t> order(vpls.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return assignment[a] < assignment[b]; });
  std::vector<uint32_t> counts(cluster_count, 0);
  std::vector<GpuVpl> sorted(vpls.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    sorted[i] = vpls[order[i]];
    sorted[i].position_cluster.w = static_cast<float>(cluster_offset + assignment[order[i]]);
    ++counts[assignment[order[i]]];
  }
  vpls = std::move(sorted);
  return counts;
}

std::vector<ssvp::ClusterPoint> cluster_points_of(std::span<const GpuVpl> vpls) {
  std::vector<ssvp::ClusterPoint> points;
  points.reserve(vpls.size());
  for (const GpuVpl& v : vpls) points.push_back({glm::vec3(v.position_cluster), glm::vec3(v.normal)});
  return points;
}

// Each cluster's paraboloid map: its eye and axis.
struct ClusterEyes {
  std::vector<glm::vec3> position, axis;
};

// The paper's prototype sits at the members' mean (Sec. II-B), which it warns "may appear as floating in space":
// the mean of VPLs on a floor and on a block's top lies inside the block, and a paraboloid map seen from there
// hides everything, dimming the whole cluster's light. The map's eye is instead the member nearest that mean, a
// point on a lit surface, lifted off it by `lift` along its own normal, which is also the map's axis: about the
// members' mean normal, the eye's own surface would rise above the map's horizon and, seen at grazing angles,
// hide the receivers on it (a third of a wall's light in Ssvp.ParaboloidEyeOnALitSurface).
ClusterEyes cluster_eyes(std::span<const ssvp::ClusterPoint> points, const ssvp::Clustering& clustering, float lift) {
  const std::size_t count = clustering.clusters.size();
  std::vector<std::size_t> eye_member(count, 0);
  std::vector<float> eye_distance(count, std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const uint32_t c = clustering.assignment[i];
    const glm::vec3 d = points[i].position - clustering.clusters[c].position;
    if (glm::dot(d, d) < eye_distance[c]) eye_distance[c] = glm::dot(d, d), eye_member[c] = i;
  }
  ClusterEyes eyes;
  for (std::size_t c = 0; c < count; ++c) {
    const ssvp::ClusterPoint& member = points[eye_member[c]];
    eyes.position.push_back(member.position + member.normal * lift);
    eyes.axis.push_back(member.normal);
  }
  return eyes;
}

// Clustered visibility tests a member's light from its cluster's eye (cluster_visibility in ssvp_shade.frag): the
// member lights what the eye sees. A member on the other side of a wall from its eye lights the eye's side through
// the wall, and one that sees the eye may still see another part of the view than the eye does: a VPL on the
// floor of a lit room whose cluster's eye stands beyond a doorway lit the whole next room from the eye's side
// (the two rooms' side walls 1.5-1.8 times Cycles'). So each member joins, among the clusters whose eyes it sees,
// the one whose eye agrees best with it on the view samples: least of the member's light at the probes where
// its own visibility and the eye's (as the map decides it: a probe behind the map's hemisphere counts as seen)
// differ. Ties go to the cluster nearest under Eq. 2, the member's own first. A member that sees no eye stays.
void agree_with_eyes(std::span<const GpuVpl> members, std::span<const ssvp::Cluster> clusters, const ClusterEyes& eyes,
                     std::span<const Probe> probes, const ssvp::ClusterMetric& metric, const cpu::CpuScene& scene,
                     float clamp, std::vector<uint32_t>& assignment) {
  const float offset = scene.ray_offset();
  const std::size_t cluster_count = clusters.size(), probe_count = probes.size();
  std::vector<uint8_t> eye_sees(cluster_count * probe_count);
  parallel_for(cluster_count, 0, 1, [&](std::size_t c) {
    for (std::size_t p = 0; p < probe_count; ++p) {
      const glm::vec3 target = probes[p].position + probes[p].normal * offset;
      eye_sees[c * probe_count + p] =
          glm::dot(target - eyes.position[c], eyes.axis[c]) <= 0.0f || scene.clear_between(eyes.position[c], target);
    }
  });
  parallel_for(members.size(), 0, 8, [&](std::size_t i) {
    const glm::vec3 position(members[i].position_cluster), normal(members[i].normal);
    const cpu::Vpl vpl{position, normal, glm::vec3(members[i].flux)};
    std::vector<float> light(probe_count, 0.0f);
    std::vector<uint8_t> sees(probe_count, 0);
    for (std::size_t p = 0; p < probe_count; ++p) {
      const glm::vec3 e = probes[p].albedo * cpu::vpl_irradiance(vpl, probes[p].position, probes[p].normal, clamp);
      light[p] = e.r + e.g + e.b;
      if (light[p] > 0.0f)
        sees[p] = scene.clear_between(position + normal * offset, probes[p].position + probes[p].normal * offset);
    }
    std::vector<std::tuple<float, float, uint32_t>> ranked;  // (disagreement, Eq. 2 distance, cluster)
    for (uint32_t c = 0; c < cluster_count; ++c) {
      float disagreement = 0.0f;
      for (std::size_t p = 0; p < probe_count; ++p)
        if (sees[p] != eye_sees[c * probe_count + p]) disagreement += light[p];
      const float distance =
          c == assignment[i] ? -1.0f
                             : ssvp::ssvp_cluster_distance(position, normal, clusters[c].position, clusters[c].normal,
                                                           metric.w1, metric.w2, metric.length_scale);
      ranked.emplace_back(disagreement, distance, c);
    }
    std::sort(ranked.begin(), ranked.end());
    for (const auto& [disagreement, distance, c] : ranked)
      if (scene.clear_between(position + normal * offset, eyes.position[c])) {
        assignment[i] = c;
        return;
      }
  });
}

struct VplClusters {
  std::vector<ssvp::Cluster> clusters;
  ClusterEyes eyes;
  std::vector<uint32_t> counts;  // members per cluster, once agree_with_eyes has moved some
};

// Clusters `vpls` into at most `k` clusters by k-means under Eq. 2 (seeded with the previous frame's clusters,
// Sec. III-C), gives each its eye, moves members to the eyes that agree with them on the view samples `probes`
// when the scene can be traced (agree_with_eyes), and sorts the VPLs by cluster (sort_by_cluster).
VplClusters cluster_vpls(std::vector<GpuVpl>& vpls, int k, const ssvp::ClusterMetric& metric,
                         std::span<const ssvp::Cluster> seeds, uint32_t seed, float lift, const cpu::CpuScene* traced,
                         std::span<const Probe> probes, float clamp, uint32_t cluster_offset) {
  const std::vector<ssvp::ClusterPoint> points = cluster_points_of(vpls);
  const ssvp::Clustering clustering = ssvp::cluster_points(points, k, metric, seeds, seed);
  VplClusters result{clustering.clusters, {}, {}};
  if (result.clusters.empty()) return result;
  result.eyes = cluster_eyes(points, clustering, lift);
  std::vector<uint32_t> assignment = clustering.assignment;
  if (traced) agree_with_eyes(vpls, result.clusters, result.eyes, probes, metric, *traced, clamp, assignment);
  result.counts = sort_by_cluster(vpls, assignment, cluster_offset, result.clusters.size());
  for (std::size_t c = 0; c < result.clusters.size(); ++c) result.clusters[c].count = result.counts[c];
  return result;
}

// The clusters as the shaders read them: each one's eye, its map's frame and its members' range.
std::vector<GpuCluster> gpu_clusters(const VplClusters& clustered) {
  std::vector<GpuCluster> result;
  uint32_t first = 0;
  for (std::size_t c = 0; c < clustered.clusters.size(); ++c) {
    const glm::vec3 axis = clustered.eyes.axis[c], tangent = any_perpendicular(axis);
    result.push_back({glm::vec4(clustered.eyes.position[c], static_cast<float>(first)),
                      glm::vec4(axis, static_cast<float>(clustered.counts[c])), glm::vec4(tangent, 0.0f),
                      glm::vec4(glm::cross(axis, tangent), 0.0f)});
    first += clustered.counts[c];
  }
  return result;
}

// Second-bounce VPLs traced (not in the paper; with VPL Importance, which has Embree's copy of the scene): cosine
// rays from the first-bounce candidates, drawn in proportion to their flux; each hit is a candidate carrying its
// albedo times the flux its ray carries, and `wanted` of them are kept by importance, as the first bounce's are.
// The paper's propagation (Sec. II-B, ssvp_propagate.comp) puts them where the first-bounce clusters' eyes look
// and gives them the cluster members' light there: it misses the surfaces no eye sees, and the light that
// reaches the view only through a second surface, which VPL Importance's members do not carry (the sunlit tops
// of window slats light the slats' undersides, which light the room; the ground outside lights the ceiling). On
// the budget's sunlit interior it gave 0.68 of Cycles' second bounce (0.60 with the members' light traced from
// every candidate, unshadowed); traced, 0.95.
std::vector<GpuVpl> trace_second_bounce(std::span<const GpuVpl> sources, int wanted, std::span<const Probe> probes,
                                        std::span<const Probe> fine_probes, const cpu::CpuScene& scene, float clamp,
                                        uint32_t seed) {
  std::vector<float> power(sources.size());
  for (std::size_t i = 0; i < sources.size(); ++i) power[i] = sources[i].flux.r + sources[i].flux.g + sources[i].flux.b;
  if (std::none_of(power.begin(), power.end(), [](float value) { return value > 0.0f; })) return {};
  const int rays = wanted * cpu::kCandidatesPerVpl;
  const std::vector<cpu::Draw> draws = cpu::resample(power, rays, 0.0f, hash_to_unit(seed));
  const float offset = scene.ray_offset();
  // Hits per unit area at y facing n, per ray, unshadowed: sum_i p_i cos_i cos_y / (pi d_i^2), over at most
  // kDensitySources candidates evenly spread (the sum scaled up by the stride).
  constexpr std::size_t kDensitySources = 256;
  const std::size_t stride = (sources.size() + kDensitySources - 1) / kDensitySources;
  double total_power = 0.0;
  for (float value : power) total_power += std::max(value, 0.0f);
  const auto hit_density = [&](glm::vec3 y, glm::vec3 n) {
    double density = 0.0;
    for (std::size_t i = 0; i < sources.size(); i += stride) {
      const glm::vec3 to_y = y - glm::vec3(sources[i].position_cluster);
      const float d2 = glm::dot(to_y, to_y);
      if (!(d2 > 0.0f) || !(power[i] > 0.0f)) continue;
      const glm::vec3 l = to_y / std::sqrt(d2);
      density += double(power[i]) * std::max(glm::dot(glm::vec3(sources[i].normal), l), 0.0f) *
                 std::max(-glm::dot(n, l), kMinSecondCosine) / (kPi * std::max(d2, clamp * clamp));
    }
    return float(density * double(stride) / total_power);
  };
  std::vector<GpuVpl> hits(draws.size(), GpuVpl{});
  parallel_for(draws.size(), 0, 16, [&](std::size_t k) {
    const GpuVpl& source = sources[draws[k].index];
    const glm::vec3 x(source.position_cluster), n(source.normal);
    const uint32_t key = hash_combine(seed, static_cast<uint32_t>(k));
    const glm::vec3 direction = cosine_direction(n, hash_to_unit(key), hash_to_unit(key ^ 0x9e3779b9u));
    const std::optional<embree::Hit> hit =
        scene.intersect(x + n * offset, direction, 0.0f, std::numeric_limits<float>::infinity());
    if (!hit) return;
    const cpu::Surface surface = scene.surface(*hit, direction);
    // The area the hit stands for, which caps the irradiance it gives (vpl_irradiance in ssvp_common.glsl):
    // 1 / (rays x the density of hits there), summed over the candidates (the density of the one that cast the
    // ray alone made the areas hundreds of times too large, and the cap darkened every corner).
    const float area = 1.0f / (float(rays) * hit_density(surface.position, surface.shading_normal));
    const glm::vec3 flux = glm::vec3(source.flux) * draws[k].weight * surface.albedo;
    if (!(flux.r + flux.g + flux.b > 0.0f) || !std::isfinite(flux.r + flux.g + flux.b + area)) return;
    hits[k] = {glm::vec4(surface.position, 0.0f), glm::vec4(surface.shading_normal, area), glm::vec4(flux, 1.0f)};
  });
  std::erase_if(hits, [](const GpuVpl& v) { return v.flux.w == 0.0f; });
  return keep_by_importance(hits, candidate_importance(hits, probes, fine_probes, scene, clamp), wanted,
                            hash_to_unit(hash_combine(seed, 1u)));
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

void SsvpPass::generate(const RenderContext& context, const GBufferPass& gbuffers, const cpu::CpuScene* traced,
                        const SceneLights& sample_lights) {
  const std::size_t lamp_count = sample_lights.lamp_count();
  first_count_ = second_count_ = 0;
  main_light_ = -1;
  clusters_.clear();
  first_bounce_candidates_.clear();
  const glm::vec3 lo = context.scene.bounds_min(), hi = context.scene.bounds_max();
  const float scene_radius = context.scene.radius();
  if (!context.scene.has_geometry() || !(scene_radius > 0.0f) || !std::isfinite(scene_radius)) return;
  const auto& lights = context.lights;
  const BounceSettings& s = context.settings;
  if (traced && traced->triangle_count() == 0) traced = nullptr;  // nothing to trace: the paper's VPLs
  first_wanted_ = std::clamp(s.ssvp_vpls, 1, 1 << 16);
  second_wanted_ = std::clamp(s.ssvp_second_vpls, 1, 1 << 16);
  const int candidates = traced ? first_wanted_ * cpu::kCandidatesPerVpl : first_wanted_;
  // No more draws than candidates, so that each light drawn gets one.
  const float rotation = hash_to_unit(hash_combine(context.seed, 0x5355u));
  const int draw_count = std::clamp(s.ssvp_bouncing_lights, 1, std::min(64, candidates));
  std::vector<float> flux_factors(lights.size(), 1.0f);
  std::copy(sample_lights.world_guide_factors().begin(), sample_lights.world_guide_factors().end(),
            flux_factors.begin() + std::ptrdiff_t(lamp_count));
  const std::vector<ssvp::LightDraw> draws =
      ssvp::draw_bouncing_lights(lights, 0.5f * (lo + hi), scene_radius, draw_count,
                                 r2_point(context.sample, glm::vec2(rotation)).x, flux_factors);
  if (draws.empty()) return;
  main_light_ = std::max_element(draws.begin(), draws.end(), [](const auto& a, const auto& b) {
                  return a.draws < b.draws;
                })->index;

  SsvpParams& p = params_;
  p = {};
  p.tiles_per_axis = 1 << std::clamp(s.ssvp_tiling, 0, 4);
  p.epsilon = s.ssvp_distance_clamp * scene_radius;
  p.length_scale = 2.0f * scene_radius;
  p.w1 = s.ssvp_position_weight;
  p.w2 = s.ssvp_normal_weight;
  p.paraboloid_far = 2.2f * p.length_scale;
  p.bounces = std::clamp(s.bounces, 1, 2);
  p.pattern_rotation = static_cast<int32_t>(hash_combine(context.seed, context.sample) % 65536u);

  if (context.sample == 0 || guides_.size() != lamp_count) guides_.assign(lamp_count, cpu::EmissionGuide{});
  // Each light drawn m times of `draw_count` samples m / draw_count of the candidates.
  prepare_candidates(context, static_cast<uint32_t>(candidates));
  rsms_.resize(std::max(rsms_.size(), draws.size()));
  std::vector<bool> claimed(rsms_.size(), false);
  int drawn_before = 0;
  for (const ssvp::LightDraw& draw : draws) {
    const uint32_t begin = static_cast<uint32_t>(int64_t(candidates) * drawn_before / draw_count);
    drawn_before += draw.draws;
    const uint32_t end = static_cast<uint32_t>(int64_t(candidates) * drawn_before / draw_count);
    const std::size_t index = static_cast<std::size_t>(draw.index);
    BounceLight light = lights[index];
    const Rsm& rsm = render_rsm(context, gbuffers, light, claimed);
    for (float& c : light.intensity) c *= draw.weight;
    sample_first_bounce(context, rsm, light, traced && index < guides_.size() ? &guides_[index] : nullptr, begin,
                        end - begin);
  }
  p.first_count = candidates;
  p.first_offset = 0;
  std::vector<Probe> probes, fine_probes;
  if (traced) {
    StageScope scope(context.timer, Stage::SsvpImportance);
    probes = cpu::camera_probes(context.view_projection, *traced, importance_key(context));
    fine_probes = cpu::camera_probes(context.view_projection, *traced, hash_combine(importance_key(context), 1u),
                                     kFineProbesPerAxis);
  }
  // Traced with VPL Importance, else propagated below.
  std::vector<GpuVpl> second = cluster(context, traced, probes, fine_probes);
  if (clusters_.empty() && second.empty()) {
    first_count_ = 0;
    return;
  }
  // A second-bounce VPL is shadowed by the map of its own cluster of second-bounce VPLs (not in the paper, which
  // tests it from the eye of the first-bounce cluster nearest it: it then lit only what that eye sees, and a
  // Cornell box's second bounce was 0.78 of Cycles', 1.03 unshadowed; 0.88 with their own maps).
  const int first_layers = static_cast<int>(clusters_.size());
  allocate_paraboloids(context, first_layers + (p.bounces > 1 ? clusters_per_bounce(context.settings) : 0));
  render_paraboloids(context, 0, first_layers);
  second_clusters_.clear();
  if (p.bounces > 1) {
    if (!traced) {
      propagate(context);
      second = read_propagated();
    }
    cluster_second_bounce(context, std::move(second), traced, probes);
    render_paraboloids(context, first_layers, first_layers + static_cast<int>(second_clusters_.size()));
  }
}

void SsvpPass::shade(const RenderContext& context, const GBuffer& camera,
                     const std::optional<RayCheckSettings>& checks) {
  if (!active()) return;
  shade_vpls(context, camera, checks);
  draw_debug(context, camera);
}

const SsvpPass::Rsm& SsvpPass::render_rsm(const RenderContext& context, const GBufferPass& gbuffers,
                                          const BounceLight& light, std::vector<bool>& claimed) {
  const LightViewKind kind = light_view_kind(light);
  // A cube's faces sit in a 3 x 2 atlas, so one Hammersley set over the atlas samples all of them.
  const int faces_x = kind == kLightViewCube ? 3 : 1, faces_y = kind == kLightViewCube ? 2 : 1;
  const int size = size_within_budget(std::clamp(context.settings.ssvp_rsm_size, 16, 8192), 64, faces_x * faces_y,
                                      kGBufferBytesPerTexel, kRsmMemoryBudget / double(rsms_.size()));
  const auto kept = [&](const Rsm& rsm) {
    return rsm.gbuffer.width == faces_x * size && rsm.gbuffer.height == faces_y * size &&
           rsm.geometry_version == context.scene.geometry_version() &&
           std::memcmp(&rsm.light, &light, sizeof light) == 0;
  };
  std::size_t slot = 0;
  while (slot < rsms_.size() && (claimed[slot] || !kept(rsms_[slot]))) ++slot;
  if (slot == rsms_.size()) slot = std::size_t(std::find(claimed.begin(), claimed.end(), false) - claimed.begin());
  claimed[slot] = true;
  Rsm& rsm = rsms_[slot];
  if (!kept(rsm)) {
    StageScope scope(context.timer, Stage::SsvpRsm);
    if (rsm.gbuffer.width != faces_x * size || rsm.gbuffer.height != faces_y * size)
      rsm.gbuffer = make_gbuffer(faces_x * size, faces_y * size);
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
    gbuffers.render(rsm.gbuffer, faces, context.scene);
    rsm.light = light;
    rsm.geometry_version = context.scene.geometry_version();
    rsm.face_size = size;
    rsm.faces_x = faces_x;
    rsm.faces_y = faces_y;
    rsm.kind = kind;
    rsm.origin = origin;
    rsm.texel_factor = views.texel_factor;
    gl::check("rendering the reflective shadow map");
  }
  return rsm;
}

void SsvpPass::prepare_candidates(const RenderContext& context, uint32_t count) {
  SsvpParams& p = params_;
  // The second bounce's disk points follow the first-bounce points in the same buffer, once cluster() knows
  // how many of those found a surface.
  const int clusters_wanted = clusters_per_bounce(context.settings);
  p.second_per_cluster =
      std::max(kMinSecondPerCluster,
               (std::clamp(context.settings.ssvp_second_vpls, 1, 1 << 16) + clusters_wanted - 1) / clusters_wanted);
  const glm::vec2 rotation = sample_rotation(context);
  disk_points_ = ssvp::disk_set(static_cast<uint32_t>(p.second_per_cluster), glm::vec2(rotation.y, rotation.x));
  candidate_points_.assign(count, glm::vec2(0.0f));
  candidate_weights_.assign(count, 1.0f);
  candidate_guides_.assign(count, nullptr);
  sample_guides_.clear();
  gl::reserve_buffer(points_, points_capacity_, (count + disk_points_.size()) * sizeof(glm::vec2));
  gl::reserve_buffer(first_vpls_, first_capacity_, count * sizeof(GpuVpl));
}

void SsvpPass::sample_first_bounce(const RenderContext& context, const Rsm& rsm, const BounceLight& light,
                                   cpu::EmissionGuide* guide, uint32_t offset, uint32_t count) {
  StageScope scope(context.timer, Stage::SsvpCluster);
  SsvpParams& p = params_;
  p.light_origin[0] = rsm.origin.x;
  p.light_origin[1] = rsm.origin.y;
  p.light_origin[2] = rsm.origin.z;
  p.light_origin[3] = static_cast<float>(rsm.kind);
  p.rsm_face_size = rsm.face_size;
  p.rsm_faces_x = rsm.faces_x;
  p.rsm_faces_y = rsm.faces_y;
  p.rsm_texel_factor = rsm.texel_factor;
  p.first_offset = static_cast<int32_t>(offset);
  p.first_count = static_cast<int32_t>(count);
  const double texels = double(rsm.gbuffer.width) * rsm.gbuffer.height;
  p.texels_per_vpl = static_cast<float>(texels / count);
  // The area a VPL stands for caps the light it gives (vpl_irradiance in ssvp_common.glsl). Each light's share of
  // the candidates would make it that light's texels / its share: a light drawn once of four would have its cap
  // four times as strict as when it was drawn alone, and the cap's bias (it does not fade over samples, only with
  // more VPLs) grew: a sky-lit room's first bounce stayed at 1.2e-4 relMSE from 16 to 64 samples. So the cap
  // keeps the area as if the light had all the sample's candidates, as one light bounced alone has.
  p.texels_per_capped_vpl = static_cast<float>(texels / candidate_points_.size());
  const glm::vec2 rotation = sample_rotation(context);
  const std::vector<glm::vec2> set = ssvp::hammersley_set(count, rotation);
  // A guided candidate's cell follows the set's first coordinate (stratified), its place in the cell the second
  // and an R2 coordinate; its flux and area are divided by the guide's density there (cluster()).
  if (guide) sample_guides_.push_back(guide);
  const bool guided = guide && !guide->uniform();
  for (uint32_t k = 0; k < count; ++k) {
    glm::vec2 point = set[k];
    if (guided) {
      const cpu::EmissionGuide::Sample sample = guide->sample(point.x, {point.y, r2_point(k, rotation).x});
      point = sample.emission;
      candidate_weights_[offset + k] = 1.0f / sample.density;
    }
    candidate_points_[offset + k] = point;
    candidate_guides_[offset + k] = guide;
  }
  glNamedBufferSubData(points_.id(), static_cast<GLintptr>(offset * sizeof(glm::vec2)),
                       static_cast<GLsizeiptr>(count * sizeof(glm::vec2)), candidate_points_.data() + offset);
  glNamedBufferSubData(params_buffer_.id(), 0, sizeof p, &p);

  LightBlock block = make_light_block(light);
  glNamedBufferSubData(light_buffer_.id(), 0, sizeof block, &block);
  glBindBufferBase(GL_UNIFORM_BUFFER, binding::kLightBlock, light_buffer_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, kParamsBlock, params_buffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kPointsBinding, points_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kFirstBinding, first_vpls_.id());
  rsm.gbuffer.bind_for_reading();
  glUseProgram(sample_program_.id());
  gl::dispatch_linear(count, 64);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
  gl::check("sampling the first-bounce VPLs");
}

std::vector<GpuVpl> SsvpPass::cluster(const RenderContext& context, const cpu::CpuScene* traced,
                                      std::span<const Probe> probes, std::span<const Probe> fine_probes) {
  SsvpParams& p = params_;
  std::vector<GpuVpl> candidates, second;
  {
    StageScope scope(context.timer, Stage::SsvpCluster);
    candidates = read_lit_vpls(first_vpls_readback_, first_vpls_.id(), static_cast<std::size_t>(p.first_count));
  }
  std::vector<GpuVpl> vpls = candidates;
  if (traced) {
    StageScope scope(context.timer, Stage::SsvpImportance);
    const uint32_t key = importance_key(context);
    // A candidate stands for 1 / density of the area it would without a guide (ssvp_sample.comp keeps its point's
    // index in position_cluster.w until it joins a cluster).
    for (GpuVpl& candidate : candidates) {
      const float weight = candidate_weights_[std::size_t(candidate.position_cluster.w)];
      candidate.flux = glm::vec4(glm::vec3(candidate.flux) * weight, candidate.flux.w);
      candidate.normal.w *= weight;
    }
    const std::vector<float> importance = candidate_importance(candidates, probes, fine_probes, *traced, p.epsilon);
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      const std::size_t k = std::size_t(candidates[i].position_cluster.w);
      if (candidate_guides_[k]) candidate_guides_[k]->learn(candidate_points_[k], importance[i]);
    }
    for (cpu::EmissionGuide* guide : sample_guides_) guide->update();
    vpls = keep_by_importance(candidates, importance, first_wanted_, hash_to_unit(hash_combine(key, 1u)));
    if (p.bounces > 1)
      second = trace_second_bounce(candidates, second_wanted_, probes, fine_probes, *traced, p.epsilon,
                                   hash_combine(key, 0x32u));
  }
  StageScope scope(context.timer, Stage::SsvpCluster);
  const ssvp::ClusterMetric metric{p.w1, p.w2, p.length_scale};
  const VplClusters first =
      cluster_vpls(vpls, context.settings.ssvp_clusters, metric,
                   context.settings.ssvp_temporal_seeding ? previous_clusters_ : std::vector<ssvp::Cluster>(),
                   hash_combine(context.seed, 0x4b4du), kCentreLift * p.length_scale, traced, probes, p.epsilon, 0);
  clusters_ = first.clusters;
  // With VPL Importance a sample may keep no first-bounce VPL (no candidate lights what the camera sees: a floor
  // seen from above under a sun straight above) and still have a second bounce: the candidates light surfaces out
  // of the view, which light the view.
  if (clusters_.empty() && second.empty()) return {};
  if (!clusters_.empty()) previous_clusters_ = clusters_;

  const std::vector<GpuCluster> first_clusters = gpu_clusters(first);
  for (const GpuVpl& vpl : candidates)
    first_bounce_candidates_.push_back(cpu::Vpl{.position = glm::vec3(vpl.position_cluster),
                                                .normal = glm::vec3(vpl.normal),
                                                .power = glm::vec3(vpl.flux),
                                                .area = vpl.normal.w});
  first_count_ = static_cast<uint32_t>(vpls.size());
  p.first_count = static_cast<int32_t>(first_count_);
  p.cluster_count = static_cast<int32_t>(clusters_.size());
  second_count_ = p.bounces > 1 && !traced ? static_cast<uint32_t>(p.cluster_count * p.second_per_cluster) : 0;
  p.second_count = static_cast<int32_t>(second_count_);
  // The shaders find the disk points right after the `first_count` first-bounce points.
  glNamedBufferSubData(points_.id(), static_cast<GLintptr>(first_count_ * sizeof(glm::vec2)),
                       static_cast<GLsizeiptr>(disk_points_.size() * sizeof(glm::vec2)), disk_points_.data());
  gl::upload_buffer(first_vpls_, first_capacity_, vpls.size() * sizeof(GpuVpl), vpls.data());
  // Room for the second bounce's own clusters after these (cluster_second_bounce).
  gl::reserve_buffer(clusters_buffer_, clusters_capacity_,
                     (first_clusters.size() + std::size_t(clusters_per_bounce(context.settings))) * sizeof(GpuCluster));
  glNamedBufferSubData(clusters_buffer_.id(), 0, static_cast<GLsizeiptr>(first_clusters.size() * sizeof(GpuCluster)),
                       first_clusters.data());
  if (!traced) gl::reserve_buffer(second_vpls_, second_capacity_, second_count_ * sizeof(GpuVpl));
  glNamedBufferSubData(params_buffer_.id(), 0, sizeof p, &p);
  gl::check("clustering the first-bounce VPLs");
  return second;
}

std::vector<GpuVpl> SsvpPass::read_propagated() {
  return read_lit_vpls(second_vpls_readback_, second_vpls_.id(), second_count_);
}

void SsvpPass::cluster_second_bounce(const RenderContext& context, std::vector<GpuVpl> vpls,
                                     const cpu::CpuScene* traced, std::span<const Probe> probes) {
  StageScope scope(context.timer, Stage::SsvpCluster);
  SsvpParams& p = params_;
  const ssvp::ClusterMetric metric{p.w1, p.w2, p.length_scale};
  const uint32_t offset = static_cast<uint32_t>(clusters_.size());
  const VplClusters second = cluster_vpls(
      vpls, clusters_per_bounce(context.settings), metric,
      context.settings.ssvp_temporal_seeding ? previous_second_clusters_ : std::vector<ssvp::Cluster>(),
      hash_combine(context.seed, 0x4b4d32u), kCentreLift * p.length_scale, traced, probes, p.epsilon, offset);
  second_clusters_ = second.clusters;
  if (!second_clusters_.empty()) previous_second_clusters_ = second_clusters_;
  const std::vector<GpuCluster> second_gpu_clusters = gpu_clusters(second);
  second_count_ = static_cast<uint32_t>(vpls.size());
  p.second_count = static_cast<int32_t>(second_count_);
  glNamedBufferSubData(clusters_buffer_.id(), static_cast<GLintptr>(offset * sizeof(GpuCluster)),
                       static_cast<GLsizeiptr>(second_gpu_clusters.size() * sizeof(GpuCluster)),
                       second_gpu_clusters.data());
  gl::upload_buffer(second_vpls_, second_capacity_, vpls.size() * sizeof(GpuVpl), vpls.data());
  glNamedBufferSubData(params_buffer_.id(), 0, sizeof p, &p);
  gl::check("clustering the second-bounce VPLs");
}

void SsvpPass::allocate_paraboloids(const RenderContext& context, int layers) {
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
}

void SsvpPass::render_paraboloids(const RenderContext& context, int begin, int end) {
  StageScope scope(context.timer, Stage::SsvpParaboloids);
  const int size = paraboloid_size_;
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
  for (int c = begin; c < end; ++c) {
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

void SsvpPass::shade_vpls(const RenderContext& context, const GBuffer& camera,
                          const std::optional<RayCheckSettings>& checks) {
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
  params_.image_width = context.width;
  params_.check_random = hash_combine(hash_combine(context.seed, context.sample), kRayCheckStream);
  glNamedBufferSubData(params_buffer_.id(), 0, sizeof params_, &params_);
  if (checks) ray_checks_.bind(std::size_t(context.width) * std::size_t(context.height));
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
    glBindTextureUnit(kParaboloidNormalUnit, paraboloid_normal_.id());
    glUseProgram(shade_program_.id());
    draw_fullscreen_triangle();
  }
  if (checks) {
    StageScope scope(context.timer, Stage::SsvpRayChecks);
    ray_checks_.correct(*checks, shaded_total_.id(), params_.bounces > 1 ? shaded_second_.id() : 0, width_, height_);
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
                             static_cast<GLsizei>(clusters_.size() + second_clusters_.size())};
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
