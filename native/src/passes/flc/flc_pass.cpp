#include "passes/flc/flc_pass.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <tuple>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "common/parallel.h"
#include "cpu/direct_light.h"
#include "cpu/random.h"
#include "cpu/view_probes.h"
#include "cpu/vpls.h"
#include "error.h"
#include "gl/shader.h"
#include "passes/flc/flc_math.h"
#include "sampling.h"
#include "topology/shared_glsl.h"

namespace bounce {

namespace {

constexpr GLuint kParamsBlock = 5;
constexpr GLuint kCountersBinding = 6;
constexpr GLuint kVplsBinding = 7;
constexpr GLuint kDivergentsBinding = 8;
constexpr GLuint kNoiseUnit = 11;
constexpr GLuint kSourceUnit = 12;
constexpr GLintptr kVplDrawOffset = 0;
constexpr GLintptr kDivergentDrawOffset = 4 * sizeof(uint32_t);
constexpr int kNoiseSize = 256;
constexpr std::size_t kVplBytes = 5 * 4 * sizeof(float);
static_assert(sizeof(FlcPass::HostVpl) == kVplBytes);
constexpr std::size_t kDivergentBytes = 4 * 4 * sizeof(float);
constexpr uint32_t kInitialVplCapacity = 1u << 16;
constexpr uint32_t kInitialDivergentCapacity = 1u << 12;
constexpr int kMaxRegrowths = 8;
constexpr uint64_t kTracedVplLight = 33;     // random streams: the VPLs' shadow rays (TracedDirectPass: 31, 32)
constexpr uint64_t kVplRoulette = 34;        // and which candidates are kept
constexpr uint64_t kRayMaps = 35;            // the directions of the ray maps' rays
constexpr uint64_t kRayMapShare = 36;        // which sides get one, beyond kMaxRayMaps
constexpr uint64_t kViewReach = 37;          // the view's probes a candidate's reach is measured at
constexpr int kReachProbes = 16;             // of cpu::kProbesPerAxis^2, per candidate
constexpr std::size_t kReachRays = 1 << 21;  // rays a sample at most, but one probe a candidate at least
constexpr double kPowerShare = 0.5;          // of a candidate's importance kept by its power alone (defensive)
constexpr GLuint kRayMapsBinding = 15;       // flc_splat.frag's FlcRayMaps
// Ray maps of a sample at most (2 KiB and FLC_RAY_MAP_BINS rays each): the budget's scenes make 80-180.
constexpr std::size_t kMaxRayMaps = 8192;

// A VPL's random stream: its triangle's random number (Alg. 1's) and its level. The order in which the GPU
// appends VPLs varies between runs and positions change with the scene's scale; these do not.
uint64_t vpl_key(const FlcPass::HostVpl& vpl) {
  uint32_t random = 0;
  std::memcpy(&random, &vpl.albedo_random.w, sizeof random);
  return uint64_t(random) << 8 | uint64_t(std::clamp(int(vpl.normal_level.w), 0, 255));
}

uint32_t grown(uint32_t capacity, uint64_t needed) {
  uint64_t next = std::max<uint64_t>(2ull * capacity, needed + needed / 4);
  if (next > (1ull << 28)) fail(BOUNCE_ERROR_OUT_OF_MEMORY, "Forward Light Cuts needs more than 2^28 VPLs");
  return static_cast<uint32_t>(next);
}

}  // namespace

FlcParams make_flc_params(const BounceSettings& settings, float scene_radius, uint32_t seed, uint32_t sample) {
  FlcParams p{};
  const float near = settings.flc_near_distance * scene_radius;
  p.s0 = 4.0f * 3.14159265f * near * near / static_cast<float>(std::max(settings.flc_vpls_per_pixel, 1));  // Eq. 1
  p.mu = std::max(settings.flc_mu, 1.0001f);
  p.levels = std::clamp(settings.flc_levels, 0, 16);
  p.inverse_cumulative_n = flc::flc_inverse_cumulative_area(p.s0, p.mu, p.levels);
  p.epsilon = settings.flc_epsilon * scene_radius;
  p.tiles_per_axis = 1 << std::clamp(settings.flc_tiling, 0, 4);
  p.jitter = settings.flc_jitter;
  p.divergent = settings.flc_divergent;
  p.u_rand = hash_combine(seed, 0x464c4300u + sample);  // Alg. 2: new every progressive sample
  p.scene_radius = scene_radius;
  p.d0 = near;
  p.cosine_lobe = settings.flc_cosine_lobe;
  p.draw_mu = p.mu;
  return p;
}

void set_flc_image(FlcParams& params, int width, int height) {
  params.image_width = width;
  params.image_height = height;
  params.tile_width = (width + params.tiles_per_axis - 1) / params.tiles_per_axis;
  params.tile_height = (height + params.tiles_per_axis - 1) / params.tiles_per_axis;
}

FlcPass::FlcPass()
    : regular_(gl::build_program(
          {{GL_VERTEX_SHADER, "flc/flc_generate.vert"}, {GL_GEOMETRY_SHADER, "flc/flc_generate.geom"}})),
      divergent_(gl::build_program({{GL_VERTEX_SHADER, "flc/flc_divergent.vert"},
                                    {GL_TESS_CONTROL_SHADER, "flc/flc_divergent.tesc"},
                                    {GL_TESS_EVALUATION_SHADER, "flc/flc_divergent.tese"},
                                    {GL_GEOMETRY_SHADER, "flc/flc_divergent.geom"}})),
      lighting_(gl::build_program({{GL_COMPUTE_SHADER, "flc/flc_light.comp"}})),
      splat_(gl::build_program({{GL_VERTEX_SHADER, "flc/flc_splat.vert"},
                                {GL_GEOMETRY_SHADER, "flc/flc_splat.geom"},
                                {GL_FRAGMENT_SHADER, "flc/flc_splat.frag"}})),
      untile_(gl::build_program(
          {{GL_VERTEX_SHADER, "common/fullscreen.vert"}, {GL_FRAGMENT_SHADER, "flc/flc_untile.frag"}})),
      levels_program_(gl::build_program(
          {{GL_VERTEX_SHADER, "flc/flc_levels.vert"}, {GL_FRAGMENT_SHADER, "common/flat_colour.frag"}})),
      params_buffer_(gl::make_buffer(sizeof(FlcParams), nullptr)),
      counters_(gl::make_buffer(sizeof(Counters), nullptr)) {
  // Alg. 2's noise texture: one uniform uint32 per texel.
  std::vector<uint32_t> noise(std::size_t(kNoiseSize) * kNoiseSize);
  for (std::size_t i = 0; i < noise.size(); ++i) noise[i] = pcg_hash(static_cast<uint32_t>(i) ^ 0x3c6ef372u);
  noise_ = gl::make_texture_2d(GL_R32UI, kNoiseSize, kNoiseSize);
  glTextureSubImage2D(noise_.id(), 0, 0, 0, kNoiseSize, kNoiseSize, GL_RED_INTEGER, GL_UNSIGNED_INT, noise.data());
  glTextureParameteri(noise_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(noise_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  // GL draws only into a complete framebuffer, even with rasterization discarded; one without attachments is
  // complete once it has a size.
  GLuint target = 0;
  glCreateFramebuffers(1, &target);
  glNamedFramebufferParameteri(target, GL_FRAMEBUFFER_DEFAULT_WIDTH, 1);
  glNamedFramebufferParameteri(target, GL_FRAMEBUFFER_DEFAULT_HEIGHT, 1);
  generation_target_ = gl::Framebuffer(target);
  GLint max_tess_level = 64;
  glGetIntegerv(GL_MAX_TESS_GEN_LEVEL, &max_tess_level);
  max_tess_level_ = static_cast<float>(max_tess_level);
  gl::check("creating the Forward Light Cuts pass");
}

void FlcPass::generate(const RenderContext& context, int candidates) {
  vpl_count_ = divergent_count_ = 0;
  const float scene_radius = context.scene.radius();
  if (!context.scene.has_geometry() || !(scene_radius > 0.0f) || !std::isfinite(scene_radius)) return;
  params_ = make_flc_params(context.settings, scene_radius, context.seed, context.sample);
  // Candidates: Alg. 1 with S_0 / M and the level ratio sqrt(mu), so that a level-k candidate stands for
  // S_0 mu^(k/2) / M, in proportion to D_k^2 (Eq. 18 as flc_level_distance has it): every level offers a receiver
  // M N_avg candidates within its reach, where the paper's lights thin out by mu per level. Eq. 14 puts light that
  // leaves a surface at grazing angles on the coarsest levels (d = |x - y| / cos); with Lambertian lights that light
  // counts, and a level-6 light stood for 186 m^2 where a spot lit a 7 m^2 disc of floor, so that 16 samples saw
  // a few such lights or none (the two rooms' walls beside the doorway: relative deviation 0.65 between seeds).
  // add_traced_light keeps about the paper's number of each level, by their light. Eq. 16's partition depends on
  // D_k alone, so the levels' reach is unchanged.
  candidates_ = std::max(candidates, 1);
  if (candidates_ > 1) {
    params_.s0 /= float(candidates_);
    params_.draw_mu = std::sqrt(params_.mu);
  }
  params_.inverse_cumulative_n = flc::flc_inverse_cumulative_area(params_.s0, params_.draw_mu, params_.levels);
  params_.max_tess_level = max_tess_level_;
  if (!vpls_) {
    vpl_capacity_ = kInitialVplCapacity;
    divergent_capacity_ = kInitialDivergentCapacity;
    vpls_ = gl::make_buffer(vpl_capacity_ * kVplBytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
    divergents_ = gl::make_buffer(divergent_capacity_ * kDivergentBytes, nullptr, 0);
  }
  // The counts are read back once per sample: they size the lighting dispatch and tell when a buffer was too
  // small, in which case it grows and the sample's VPLs are generated again (the same ones: same randoms).
  for (int attempt = 0;; ++attempt) {
    run_pipelines(context);
    Counters counters{};
    counters_readback_.read(counters_.id(), sizeof counters, &counters);
    if (counters.vpl_overflow == 0 && counters.divergent_overflow == 0) {
      vpl_count_ = counters.vpl_draw[0];
      divergent_count_ = counters.divergent_draw[1];
      break;
    }
    if (attempt == kMaxRegrowths) fail(BOUNCE_ERROR_INTERNAL, "Forward Light Cuts: VPL buffers kept overflowing");
    if (counters.divergent_overflow) {
      divergent_capacity_ = grown(divergent_capacity_, divergent_capacity_ + uint64_t(counters.divergent_overflow));
      divergents_ = gl::make_buffer(divergent_capacity_ * kDivergentBytes, nullptr, 0);
    }
    if (counters.vpl_overflow) {
      vpl_capacity_ = grown(vpl_capacity_, vpl_capacity_ + uint64_t(counters.vpl_overflow));
      vpls_ = gl::make_buffer(std::size_t(vpl_capacity_) * kVplBytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    gl::check("growing the Forward Light Cuts buffers");
  }
}

void FlcPass::run_pipelines(const RenderContext& context) {
  params_.vpl_capacity = vpl_capacity_;
  params_.divergent_capacity = divergent_capacity_;
  glNamedBufferSubData(params_buffer_.id(), 0, sizeof params_, &params_);
  const Counters reset{{0, 1, 0, 0}, {3, 0, 0, 0}, 0, 0};
  glNamedBufferSubData(counters_.id(), 0, sizeof reset, &reset);
  glBindBufferBase(GL_UNIFORM_BUFFER, kParamsBlock, params_buffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kCountersBinding, counters_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kVplsBinding, vpls_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kDivergentsBinding, divergents_.id());
  glBindFramebuffer(GL_FRAMEBUFFER, generation_target_.id());
  glEnable(GL_RASTERIZER_DISCARD);
  {
    StageScope scope(context.timer, Stage::FlcRegular);
    glUseProgram(regular_.id());
    context.scene.draw();
  }
  if (params_.divergent) {
    StageScope scope(context.timer, Stage::FlcDivergent);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    glUseProgram(divergent_.id());
    glBindTextureUnit(kNoiseUnit, noise_.id());
    glBindVertexArray(empty_vertex_array());
    glPatchParameteri(GL_PATCH_VERTICES, 3);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, counters_.id());
    glDrawArraysIndirect(GL_PATCHES, reinterpret_cast<const void*>(kDivergentDrawOffset));
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    glBindVertexArray(0);
  }
  glDisable(GL_RASTERIZER_DISCARD);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  gl::check("generating Forward Light Cuts VPLs");
}

void FlcPass::add_light(const RenderContext& context) {
  if (vpl_count_ == 0) return;
  StageScope scope(context.timer, Stage::FlcLighting);
  glBindBufferBase(GL_UNIFORM_BUFFER, kParamsBlock, params_buffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kVplsBinding, vpls_.id());
  glUseProgram(lighting_.id());
  glUniform1ui(0, vpl_count_);
  gl::dispatch_linear(vpl_count_, 64);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  gl::check("lighting the Forward Light Cuts VPLs");
}

void FlcPass::add_traced_light(const RenderContext& context, const cpu::CpuScene& scene,
                               const SceneLights& scene_lights, const TopologyVisibilityPass* visibility) {
  if (vpl_count_ == 0 || context.lights.empty() || scene.triangle_count() == 0) return;
  StageScope scope(context.timer, Stage::FlcLighting);
  traced_vpls_.resize(std::size_t(vpl_count_));
  vpls_readback_.read(vpls_.id(), traced_vpls_.size() * sizeof(HostVpl), traced_vpls_.data());
  const cpu::ShadowRays rays{scene.bvh(), scene.ray_offset(), 1, scene.opaque(), context.settings.shadow_softness};
  const cpu::WorldStrategies world{scene_lights, context.settings.world_lights};
  const uint64_t sample = uint64_t(context.sample) << 8;
  parallel_for(traced_vpls_.size(), 0, 256, [&](std::size_t i) {
    HostVpl& vpl = traced_vpls_[i];
    const glm::vec3 y(vpl.position_scale), n(vpl.normal_level);
    cpu::Rng rng(context.seed, kTracedVplLight ^ sample, vpl_key(vpl));
    vpl.front = glm::vec4(cpu::direct_irradiance(context.lights, y, n, rays, rng, &world), 0.0f);
    vpl.back = glm::vec4(cpu::direct_irradiance(context.lights, y, -n, rays, rng, &world), 0.0f);
  });
  if (candidates_ > 1) {
    // Per level k, each candidate is kept with probability p = min(1, Q / (M_k mean_k P)) and its weight divided by
    // p: unbiased, about one in M_k kept, where M_k = M (mu / draw_mu)^k is the number of candidates a paper's light
    // of level k stands for. Q is its reflected power P (rho E, both sides, times its weight), times
    // u + (1 - u) R / mean_k R, R the light it gives what the camera sees per unit of P (view_reach; u = kPowerShare,
    // defensive): so the lights go where the light is and reaches the view. In the sunlit room the
    // lawn reflects 97 % of the sun's light and gives the room 8 % of its first bounce: kept by P alone, nearly every
    // light stood on the lawn, and the stripes the blinds let onto the floor, half of the room's light, had a few
    // coarse lights or none (a sample's mean varied by half).
    std::array<double, 17> level_power{}, level_reach{};
    std::array<uint32_t, 17> level_count{};
    const auto power = [](const HostVpl& vpl) {
      const glm::vec3 reflected = glm::vec3(vpl.albedo_random) * (glm::vec3(vpl.front) + glm::vec3(vpl.back));
      return double(reflected.r + reflected.g + reflected.b) * double(vpl.position_scale.w);
    };
    const auto level = [](const HostVpl& vpl) { return std::clamp(int(vpl.normal_level.w), 0, 16); };
    const std::vector<double> reach = view_reach(context, scene);
    for (std::size_t i = 0; i < traced_vpls_.size(); ++i) {
      const int k = level(traced_vpls_[i]);
      level_power[k] += power(traced_vpls_[i]);
      level_reach[k] += power(traced_vpls_[i]) * reach[i];
      ++level_count[k];
    }
    const auto importance = [&](std::size_t i) {
      const int k = level(traced_vpls_[i]);
      const double mean_reach = level_reach[k] / level_power[k];
      if (!(mean_reach > 0.0)) return power(traced_vpls_[i]);
      return power(traced_vpls_[i]) * (kPowerShare + (1.0 - kPowerShare) * reach[i] / mean_reach);
    };
    std::array<double, 17> level_candidates{};
    for (std::size_t k = 0; k < level_candidates.size(); ++k)
      level_candidates[k] = double(candidates_) * std::pow(double(params_.mu) / double(params_.draw_mu), double(k));
    std::size_t kept = 0;
    for (std::size_t i = 0; i < traced_vpls_.size(); ++i) {
      const HostVpl vpl = traced_vpls_[i];
      const double budget = level_candidates[level(vpl)] * level_power[level(vpl)] / double(level_count[level(vpl)]);
      const double p = budget > 0.0 ? std::min(1.0, importance(i) / budget) : 0.0;
      if (!(p > 0.0) || !(double(cpu::Rng(context.seed, kVplRoulette ^ sample, vpl_key(vpl)).next()) < p)) continue;
      traced_vpls_[kept] = vpl;
      traced_vpls_[kept++].position_scale.w = float(double(vpl.position_scale.w) / p);
    }
    traced_vpls_.resize(kept);
    vpl_count_ = uint32_t(kept);
    glNamedBufferSubData(counters_.id(), 0, sizeof vpl_count_, &vpl_count_);  // the splat's draw count
    if (kept == 0) return;
  }
  if (visibility) trace_ray_maps(context, scene, *visibility);
  glNamedBufferSubData(vpls_.id(), 0, GLsizeiptr(traced_vpls_.size() * sizeof(HostVpl)), traced_vpls_.data());
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  gl::check("lighting the Forward Light Cuts VPLs with rays");
}

std::vector<double> FlcPass::view_reach(const RenderContext& context, const cpu::CpuScene& scene) const {
  // Per candidate, the light it gives kReachProbes of the view's probes drawn at random (cpu::camera_probes), each
  // through its level's share of Eq. 16 at Eq. 14's distance and behind a shadow ray, per unit of its power: the
  // light the splat would give those pixels. Millions of candidates (the least Near Distance) take fewer probes
  // each, so that the rays stay within kReachRays.
  std::vector<double> reach(traced_vpls_.size(), 0.0);
  const uint64_t sample = uint64_t(context.sample) << 8;
  const std::vector<cpu::ViewProbe> probes =
      cpu::camera_probes(context.view_projection, scene, hash_combine(context.seed, context.sample ^ 0x464c4356u));
  if (probes.empty()) return reach;
  const float offset = scene.ray_offset(), epsilon2 = params_.epsilon * params_.epsilon;
  const int probes_per_candidate =
      int(std::clamp<std::size_t>(kReachRays / std::max<std::size_t>(traced_vpls_.size(), 1), 1, kReachProbes));
  parallel_for(traced_vpls_.size(), 0, 64, [&](std::size_t i) {
    const HostVpl& vpl = traced_vpls_[i];
    const glm::vec3 y(vpl.position_scale), n(vpl.normal_level), albedo(vpl.albedo_random);
    const int level = std::clamp(int(vpl.normal_level.w), 0, 16);
    const glm::vec3 front = albedo * glm::vec3(vpl.front), back = albedo * glm::vec3(vpl.back);
    const double power = double(front.r + front.g + front.b + back.r + back.g + back.b);
    if (!(power > 0.0)) return;
    cpu::Rng rng(context.seed, kViewReach ^ sample, vpl_key(vpl));
    double light = 0.0;
    for (int j = 0; j < probes_per_candidate; ++j) {
      const cpu::ViewProbe& probe = probes[std::min(probes.size() - 1, std::size_t(rng.next() * float(probes.size())))];
      const glm::vec3 to_probe = probe.position - y;
      const float d2 = glm::dot(to_probe, to_probe);
      if (!(d2 > 0.0f)) continue;
      const glm::vec3 direction = to_probe / std::sqrt(d2);
      const float cos_light = glm::dot(n, direction), cos_probe = -glm::dot(probe.normal, direction);
      const glm::vec3 side = cos_light > 0.0f ? front : back;
      if (!(cos_probe > 0.0f) || !(side.r + side.g + side.b > 0.0f)) continue;
      const float share =
          flc::flc_partition(std::sqrt(d2) / std::abs(cos_light), level, params_.levels, params_.d0, params_.mu);
      if (!(share > 0.0f)) continue;
      const glm::vec3 given = side * probe.albedo * (std::abs(cos_light) * cos_probe * share / std::max(d2, epsilon2));
      if (!(given.r + given.g + given.b > 0.0f)) continue;
      const glm::vec3 lift = (cos_light > 0.0f ? n : -n) * offset;
      if (scene.clear_between(y + lift, probe.position + probe.normal * offset))
        light += double(given.r + given.g + given.b);
    }
    reach[i] = light / power;
  });
  return reach;
}

void FlcPass::trace_ray_maps(const RenderContext& context, const cpu::CpuScene& scene,
                             const TopologyVisibilityPass& visibility) {
  // Where the grid closes the gaps of thin geometry (the slats of blinds, the sill under them and the window's
  // reveals, 8.8 cm apart in 11 cm voxels), a light on its surface has no empty voxel along its normal, and the
  // cluster it fell back on was a guess: the slats' sunlit tops took the outside's cluster or the room's, so their
  // light reached the room by a passage's share pooled over the whole opening, or whole, as if the slat above cast no
  // shadow. The Topology method casts such lights shadow rays; the splat has none per receiver. So each such lit
  // side gets a ray per bin of an octahedral map, drawn anew in its bin every sample. A bin keeps the cluster its ray
  // enters once it leaves the thin geometry and how far along, or, when it meets a surface first, that surface's
  // distance; the splat carries the light on from there by the topology (flc_splat.frag), so that over the samples
  // each bin passes the share of its directions that leave.
  struct Side {
    std::size_t vpl;
    bool back;
  };
  const uint64_t sample = uint64_t(context.sample) << 8;
  std::vector<Side> sides;
  for (std::size_t i = 0; i < traced_vpls_.size(); ++i) {
    HostVpl& vpl = traced_vpls_[i];
    const glm::vec3 y(vpl.position_scale), n(vpl.normal_level);
    for (const bool back : {false, true}) {
      glm::vec4& side = back ? vpl.back : vpl.front;
      side.w = 0.0f;
      if (side.r + side.g + side.b > 0.0f && !visibility.places(y, back ? -n : n)) sides.push_back({i, back});
    }
  }
  // Beyond kMaxRayMaps (a scene of thin geometry everywhere, or millions of VPLs), a share of the sides drawn by
  // their VPLs' keys, so that which ones stays the same from run to run, gets maps; the others keep their clusters.
  if (sides.size() > kMaxRayMaps) {
    const auto key = [&](const Side& side) { return std::pair{vpl_key(traced_vpls_[side.vpl]), side.back}; };
    std::sort(sides.begin(), sides.end(), [&](const Side& a, const Side& b) { return key(a) < key(b); });
    const double keep = double(kMaxRayMaps) / double(sides.size());
    std::erase_if(sides, [&](const Side& side) {
      cpu::Rng rng(context.seed, kRayMapShare ^ sample, vpl_key(traced_vpls_[side.vpl]) << 1 | uint64_t(side.back));
      return !(double(rng.next()) < keep);
    });
    sides.resize(std::min(sides.size(), kMaxRayMaps));
  }
  for (std::size_t s = 0; s < sides.size(); ++s) {
    HostVpl& vpl = traced_vpls_[sides[s].vpl];
    (sides[s].back ? vpl.back : vpl.front).w = std::bit_cast<float>(uint32_t(s + 1));
  }
  ray_maps_.assign(sides.size() * 2 * FLC_RAY_MAP_BINS, 0u);
  for (std::size_t i = 0; i < ray_maps_.size(); i += 2) ray_maps_[i] = topology::kNoNode;
  if (sides.empty()) return;
  const float offset = scene.ray_offset();
  parallel_for(sides.size(), 0, 8, [&](std::size_t s) {
    const HostVpl& vpl = traced_vpls_[sides[s].vpl];
    const glm::vec3 n = sides[s].back ? -glm::vec3(vpl.normal_level) : glm::vec3(vpl.normal_level);
    const glm::vec3 origin = glm::vec3(vpl.position_scale) + offset * n;
    cpu::Rng rng(context.seed, kRayMaps ^ sample, vpl_key(vpl) << 1 | uint64_t(sides[s].back));
    uint32_t* map = &ray_maps_[s * 2 * FLC_RAY_MAP_BINS];
    for (int bin = 0; bin < FLC_RAY_MAP_BINS; ++bin) {
      // Bins across the horizon get a direction above it when one of a few draws finds one; the splat asks only
      // for receivers above it.
      for (int draw = 0; draw < 4; ++draw) {
        const float u = rng.next(), v = rng.next();
        const glm::vec3 direction = topology::shared::octahedral_bin_direction(bin, FLC_RAY_MAP_BINS_PER_SIDE, u, v);
        if (!(glm::dot(direction, n) > 0.0f)) continue;
        const std::optional<embree::Hit> hit =
            scene.intersect(origin, direction, 0.0f, std::numeric_limits<float>::max());
        const float t = hit ? hit->t : std::numeric_limits<float>::max();
        const TopologyVisibilityPass::Entry entry = visibility.entry_along(origin, direction, t);
        map[2 * bin] = entry.cluster;
        map[2 * bin + 1] = std::bit_cast<uint32_t>(entry.cluster != topology::kNoNode ? entry.distance : t);
        break;
      }
    }
  });
  if (ray_maps_.size() > ray_maps_capacity_) {
    ray_maps_capacity_ = std::max(ray_maps_.size(), 2 * ray_maps_capacity_);
    ray_maps_buffer_ = gl::make_buffer(ray_maps_capacity_ * sizeof(uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT);
  }
  glNamedBufferSubData(ray_maps_buffer_.id(), 0, GLsizeiptr(ray_maps_.size() * sizeof(uint32_t)), ray_maps_.data());
}

void FlcPass::resize(int width, int height, const FlcParams& params) {
  const int tiled_width = params.tile_width * params.tiles_per_axis;
  const int tiled_height = params.tile_height * params.tiles_per_axis;
  if (width != width_ || height != height_) {
    untiled_ = gl::make_texture_2d(GL_RGBA32F, width, height);
    untiled_target_ = gl::make_framebuffer({untiled_.id()}, 0);
    levels_ = gl::make_texture_2d(GL_RGBA16F, width, height);
    levels_depth_ = 0;
    width_ = width;
    height_ = height;
  }
  if (tiled_width != tiled_width_ || tiled_height != tiled_height_) {
    tiled_ = gl::make_texture_2d(GL_RGBA32F, tiled_width, tiled_height);
    tiled_target_ = gl::make_framebuffer({tiled_.id()}, 0);
    tiled_width_ = tiled_width;
    tiled_height_ = tiled_height;
  }
  gl::check("allocating the Forward Light Cuts targets");
}

void FlcPass::shade(const RenderContext& context, const GBuffer& gbuffer, const TopologyVisibilityPass* visibility,
                    const std::optional<RayCheckSettings>& checks) {
  if (vpl_count_ == 0) return;
  set_flc_image(params_, context.width, context.height);
  resize(context.width, context.height, params_);
  params_.visibility = visibility != nullptr;
  glNamedBufferSubData(params_buffer_.id(), 0, sizeof params_, &params_);
  if (visibility) visibility->bind();
  // A pixel checks about one pair a sample at the default share.
  if (visibility && checks) ray_checks_.bind(std::size_t(context.width) * std::size_t(context.height));
  if (levels_depth_ != gbuffer.depth.id()) {
    levels_target_ = gl::make_framebuffer({levels_.id()}, gbuffer.depth.id());
    levels_depth_ = gbuffer.depth.id();
  }
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  glBindBufferBase(GL_UNIFORM_BUFFER, kParamsBlock, params_buffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kVplsBinding, vpls_.id());
  if (ray_maps_buffer_.id() != 0) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kRayMapsBinding, ray_maps_buffer_.id());
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, counters_.id());
  glBindVertexArray(empty_vertex_array());
  gbuffer.bind_for_reading();
  const bool tiled = params_.tiles_per_axis > 1;
  {
    StageScope scope(context.timer, Stage::FlcSplat);
    const gl::Framebuffer& target = tiled ? tiled_target_ : untiled_target_;
    glClearNamedFramebufferfv(target.id(), GL_COLOR, 0, zero);
    glBindFramebuffer(GL_FRAMEBUFFER, target.id());
    glViewport(0, 0, tiled ? tiled_width_ : width_, tiled ? tiled_height_ : height_);
    glUseProgram(splat_.id());
    glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(context.view_projection));
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    glDrawArraysIndirect(GL_POINTS, reinterpret_cast<const void*>(kVplDrawOffset));
    glDisable(GL_BLEND);
  }
  {
    StageScope scope(context.timer, Stage::FlcResolve);
    glViewport(0, 0, width_, height_);
    if (tiled) {
      glBindFramebuffer(GL_FRAMEBUFFER, untiled_target_.id());
      glUseProgram(untile_.id());
      glBindTextureUnit(kSourceUnit, tiled_.id());
      draw_fullscreen_triangle();
    }
  }
  if (visibility && checks) {
    StageScope scope(context.timer, Stage::FlcRayChecks);
    ray_checks_.correct(*checks, untiled_.id(), 0, width_, height_);
  }
  {
    StageScope scope(context.timer, Stage::FlcResolve);
    resolved_ = blur_.run(untiled_.id(), gbuffer, context.settings.flc_blur_radius);
  }
  {
    StageScope scope(context.timer, Stage::FlcSplat);
    glClearNamedFramebufferfv(levels_target_.id(), GL_COLOR, 0, zero);
    glBindFramebuffer(GL_FRAMEBUFFER, levels_target_.id());
    glUseProgram(levels_program_.id());
    glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(context.view_projection));
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
    glEnable(GL_PROGRAM_POINT_SIZE);
    glBindVertexArray(empty_vertex_array());
    glDrawArraysIndirect(GL_POINTS, reinterpret_cast<const void*>(kVplDrawOffset));
    glDisable(GL_PROGRAM_POINT_SIZE);
    glDepthMask(GL_TRUE);
    glDisable(GL_DEPTH_TEST);
  }
  glBindVertexArray(0);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  gl::check("shading Forward Light Cuts");
}

}  // namespace bounce
