#include "renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>

#include <glm/gtc/type_ptr.hpp>

#include "auto_plan.h"
#include "common/fault_injection.h"
#include "cpu/view_probes.h"
#include "error.h"
#include "sample_schedule.h"
#include "sampling.h"

namespace bounce {

namespace {

struct Tile {
  int x, y, width, height;  // in image pixels
};

constexpr double kResidentAccumulationBytes = 1 << 30;

// The stages whose work grows with the method's VPL count (cost_model.h's vpl_setting).
double vpl_stages_milliseconds(const StageTimer& timer, int32_t method) {
  if (method == BOUNCE_METHOD_TOPOLOGY)
    return timer.milliseconds(Stage::TopologyVpls) + timer.milliseconds(Stage::TopologyIndirect);
  return timer.milliseconds(Stage::SsvpImportance) + timer.milliseconds(Stage::SsvpShade);
}

// Whether sample s renews the guide of the world's directions: samples 0, 1, 2, 4, 8, ... (see render_method).
bool renews_world_guide(int s) { return (s & (s - 1)) == 0; }

// What a sample's cost depends on: the GPU (its GL renderer) and the CPU's threads (Embree, the CPU stages).
std::string device_name() {
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return std::string(renderer ? renderer : "unknown GL renderer") + " | " +
         std::to_string(std::thread::hardware_concurrency()) + " CPU threads";
}

}  // namespace

glm::mat4 tile_matrix(int image_width, int image_height, int x0, int y0, int width, int height, glm::vec2 jitter) {
  glm::mat4 m(1.0f);
  m[0][0] = static_cast<float>(image_width) / width;
  m[1][1] = static_cast<float>(image_height) / height;
  m[3][0] = -((2.0f * x0 + width) / image_width - 1.0f) * m[0][0] + 2.0f * jitter.x / width;
  m[3][1] = -((2.0f * y0 + height) / image_height - 1.0f) * m[1][1] + 2.0f * jitter.y / height;
  return m;
}

Renderer::Renderer()
    : costs_(CostModel::of_device(device_name())), settings_buffer_(gl::make_buffer(sizeof(BounceSettings), nullptr)) {}

void Renderer::bind_emitter_occluders(const std::vector<EmitterOccluder>& occluders) {
  static_assert(sizeof(EmitterOccluder) == 3 * sizeof(glm::vec4));
  const glm::uvec4 count(static_cast<uint32_t>(occluders.size()), 0u, 0u, 0u);
  const std::size_t bytes = sizeof count + occluders.size() * sizeof(EmitterOccluder);
  if (!emitter_occluders_ || emitter_occluders_bytes_ < bytes) {
    emitter_occluders_ = gl::make_buffer(bytes, nullptr);
    emitter_occluders_bytes_ = bytes;
  }
  glNamedBufferSubData(emitter_occluders_.id(), 0, sizeof count, &count);
  if (!occluders.empty())
    glNamedBufferSubData(emitter_occluders_.id(), sizeof count, GLsizeiptr(bytes - sizeof count), occluders.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kEmitterOccluders, emitter_occluders_.id());
}

bool Renderer::render(const BounceSettings& settings, const BounceCamera& camera, const RenderCallbacks& callbacks) {
  scene_.prepare();
  const bool cropped = camera.crop[2] > camera.crop[0] && camera.crop[3] > camera.crop[1];
  const int64_t pixels = cropped ? int64_t(camera.crop[2] - camera.crop[0]) * (camera.crop[3] - camera.crop[1])
                                 : int64_t(camera.width) * camera.height;
  AutoPlan plan{settings, {}, 0.0, 0.0, ""};
  if (settings.method == BOUNCE_METHOD_AUTO)
    plan = plan_auto(settings, analysis(settings, camera), costs_, pixels);
  else if (plan_frame(settings).needs_cpu_scene())  // Embree's copy is there: the analysis costs milliseconds
    plan.bias_relmse = accepted_bias(settings, analysis(settings, camera));
  // Every frame published teaches the cost model, whichever method it had, a cancelled render's too (the viewport
  // restarts while one navigates): the share of the VPLs' stages in the stage timer's total splits its time. The
  // topology's precomputation is paid once per scene, not per sample.
  const auto started = std::chrono::steady_clock::now();
  double sample_ms = 0.0, vpl_share = 0.0;
  RenderCallbacks annotated = callbacks;
  annotated.publish = [&](std::shared_ptr<Frame> frame) {
    const double precompute_ms = timer_.milliseconds(Stage::TopologyPrecompute);
    sample_ms = (std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count() -
                 precompute_ms) /
                std::max(frame->info.samples, 1);
    const double total_ms = timer_.total_milliseconds() - precompute_ms;
    vpl_share = total_ms > 0.0 ? vpl_stages_milliseconds(timer_, plan.settings.method) / total_ms : 0.0;
    frame->info.method = plan.settings.method;
    frame->info.bounces = plan_frame(plan.settings).bounces;
    const std::string used = plan.budget_ms > 0.0 ? " Used " + std::to_string(std::lround(sample_ms)) + " ms." : "";
    std::snprintf(frame->info.plan, sizeof frame->info.plan, "%s", (plan.summary + used).c_str());
    frame->info.shares = plan.shares;
    frame->info.bias_relmse = float(plan.bias_relmse);
    callbacks.publish(std::move(frame));
  };
  const bool finished = render_method(plan.settings, camera, annotated);
  if (sample_ms > 0.0) costs_.observe(plan.settings, pixels, sample_ms, vpl_share);
  return finished;
}

const cpu::SceneAnalysis& Renderer::analysis(const BounceSettings& settings, const BounceCamera& camera) {
  cpu_scene_.sync(scene_);
  const glm::mat4 world_to_view = glm::make_mat4(camera.world_to_view);
  const glm::mat4 view_to_world = glm::inverse(world_to_view);
  const AnalysisKey key{scene_.geometry_version(), scene_.light_version(), scene_.world_version(),
                        glm::vec3(view_to_world[3]), -glm::normalize(glm::vec3(view_to_world[2]))};
  constexpr float kMoved = 0.05f;          // of the scene's radius
  constexpr float kTurnedCosine = 0.985f;  // 10 degrees
  const AnalysisKey& old = analysis_key_;
  const bool same_scene = key.geometry == old.geometry && key.lights == old.lights && key.world == old.world;
  if (same_scene && glm::distance(key.eye, old.eye) <= kMoved * cpu_scene_.radius() &&
      glm::dot(key.forward, old.forward) >= kTurnedCosine) {
    analysis_.milliseconds = 0.0;  // kept: it cost this render nothing
    return analysis_;
  }
  analysis_key_ = key;
  // The world's and the emitters' light from more directions and triangles than a sample draws: the analysis
  // measures their share once, whatever the settings.
  constexpr int kAnalysisSourceLights = 64;
  BounceSettings probe_settings = settings;
  probe_settings.world_lights = kAnalysisSourceLights;
  probe_settings.emission_lights = kAnalysisSourceLights;
  const uint32_t seed = hash_combine(static_cast<uint32_t>(settings.seed), static_cast<uint32_t>(camera.frame));
  const std::vector<BounceLight>& lights = scene_lights_.sample(scene_, probe_settings, 0, seed);
  const BounceWorld& world = scene_.world();
  const cpu::AnalysisView view{world_to_view, glm::make_mat4(camera.projection),
                               float(std::max(camera.width, 1)) / float(std::max(camera.height, 1)),
                               !world.transparent && !world.camera_hidden};
  analysis_ = cpu::analyse_scene(cpu_scene_, {lights, scene_lights_.lamp_count(), scene_lights_.world_count()}, view,
                                 WorldRadiance(world, scene_.texture_data(world.environment_texture)), seed);
  return analysis_;
}

bool Renderer::render_method(const BounceSettings& settings, const BounceCamera& camera,
                             const RenderCallbacks& callbacks) {
  const FramePlan plan = plan_frame(settings);
  if (plan.indirect == FramePlan::Indirect::Topology)
    return topology_.render(scene_, scene_lights_, settings, camera, callbacks, timer_);
  glNamedBufferSubData(settings_buffer_.id(), 0, sizeof settings, &settings);
  glBindBufferBase(GL_UNIFORM_BUFFER, binding::kSettingsBlock, settings_buffer_.id());
  int x0 = camera.crop[0], y0 = camera.crop[1], x1 = camera.crop[2], y1 = camera.crop[3];
  if (x0 == 0 && y0 == 0 && x1 == 0 && y1 == 0) {
    x1 = camera.width;
    y1 = camera.height;
  }
  const glm::mat4 world_to_view = glm::make_mat4(camera.world_to_view);
  const glm::mat4 projection = glm::make_mat4(camera.projection);
  const glm::mat4 view_to_world = glm::inverse(world_to_view);
  const uint32_t seed = hash_combine(static_cast<uint32_t>(settings.seed), static_cast<uint32_t>(camera.frame));
  const glm::vec2 jitter_rotation(hash_to_unit(hash_combine(seed, 101)), hash_to_unit(hash_combine(seed, 102)));

  // Tiles of one size, at most tile_size a side, so that every pass keeps its targets across a sample's tiles (the
  // smaller tiles at the frame's edges made each pass reallocate them twice a sample). The last column and row reach
  // past the frame by fewer pixels than there are columns or rows; those pixels are rendered and left out.
  const auto ceil_div = [](int a, int b) { return (a + b - 1) / b; };
  const int columns = ceil_div(x1 - x0, settings.tile_size), rows = ceil_div(y1 - y0, settings.tile_size);
  const int tile_width = ceil_div(x1 - x0, columns), tile_height = ceil_div(y1 - y0, rows);
  std::vector<Tile> tiles;
  for (int row = 0; row < rows; ++row)
    for (int column = 0; column < columns; ++column)
      tiles.push_back({x0 + column * tile_width, y0 + row * tile_height, tile_width, tile_height});

  auto frame = std::make_shared<Frame>();
  const uint32_t aov_bits = method_aovs(settings.method);
  frame->allocate(x1 - x0, y1 - y0, aov_bits);
  timer_.reset();
  const int samples = settings.samples;
  const int total_steps = samples * static_cast<int>(tiles.size());

  // Tiles keep the sums of their samples in accumulation targets of their own while the frame's fit in
  // kResidentAccumulationBytes, and are read back when a frame is published, as one image is. Larger frames' tiles
  // take turns with one set of targets, each adding every sample into the frame on the host, so that GPU memory
  // stays bounded by the tile size; that readback made a sample of FLC and SSVP 1.06-1.23x as long in 256-pixel
  // tiles as untiled at 1280x720 on an H100, 1.12-1.19x on llvmpipe.
  const bool tiles_take_turns = tiles.size() > 1 && (double(x1 - x0) * double(y1 - y0) * ComposePass::kBytesPerPixel >
                                                         kResidentAccumulationBytes ||
                                                     fault_injected("low-gpu-memory"));
  compose_.keep_slots(tiles_take_turns ? 1 : static_cast<int>(tiles.size()));
  const auto slot_of = [&](std::size_t tile) { return tiles_take_turns ? 0 : static_cast<int>(tile); };
  auto read_tile = [&](Frame& into, std::size_t t, int samples_done, ComposePass::Into how) {
    StageScope scope(timer_, Stage::Readback);
    compose_.read(slot_of(t), samples_done, into, tiles[t].x - x0, tiles[t].y - y0, how);
  };
  auto read_frame = [&](Frame& into, int samples_done) {
    for (std::size_t t = 0; t < tiles.size(); ++t) read_tile(into, t, samples_done, ComposePass::Into::Replace);
  };
  const bool flc = plan.indirect == FramePlan::Indirect::ForwardLightCuts;
  const bool ssvp = plan.indirect == FramePlan::Indirect::Ssvp;
  const bool traced_direct = plan.direct == FramePlan::Direct::RayTraced;
  const bool flc_visibility = flc && plan.indirect_shadows;
  if (plan.needs_cpu_scene()) cpu_scene_.sync(scene_);
  const float near_field_clamp = plan.near_field_clamp * scene_.radius();  // metres
  if (flc_visibility) {
    const std::shared_ptr<const topology::Topology> before = flc_topologies_.latest();
    std::shared_ptr<const topology::Topology> topology;
    {
      StageScope scope(timer_, Stage::TopologyPrecompute);
      topology = flc_topologies_.get(cpu_scene_, settings, callbacks);
    }
    if (!topology) return false;                         // cancelled while building
    if (topology != before) callbacks.status("", 0.0f);  // clears the build's stage text
    topology_visibility_.prepare(topology);
  }
  uint32_t vpl_count = 0, divergent_count = 0, cluster_count = 0;
  int main_light = -1;
  auto finish_info = [&](Frame& into, int samples_done) {
    timer_.resolve();
    into.info.vpl_count = vpl_count;
    into.info.divergent_triangles = divergent_count;
    into.info.main_light = main_light;
    into.info.cluster_count = static_cast<int32_t>(cluster_count);
    into.info.width = into.width;
    into.info.height = into.height;
    into.info.samples = samples_done;
    timer_.fill(into.info);
  };
  auto view_projection_of = [&](const Tile& tile, glm::vec2 jitter) {
    return tile_matrix(camera.width, camera.height, tile.x, tile.y, tile.width, tile.height, jitter) * projection *
           world_to_view;
  };
  auto context_of = [&](const Tile& tile, uint32_t sample, glm::vec2 jitter, const std::vector<BounceLight>& lights) {
    return RenderContext{scene_,
                         lights,
                         settings,
                         timer_,
                         tile.width,
                         tile.height,
                         glm::ivec2(tile.x, tile.y),
                         view_projection_of(tile, jitter),
                         world_to_view,
                         glm::vec3(view_to_world[3]),
                         -glm::normalize(glm::vec3(view_to_world[2])),
                         projection[2][3] == 0.0f,
                         sample,
                         seed};
  };

  // Samples outside, tiles inside: what a sample computes whatever the view (shadow maps, Forward Light Cuts'
  // and SSVP's VPLs) is computed once and shared by its tiles. ShadowPass keeps each light's map until the sample
  // changes.
  if (!tiles_take_turns)
    for (std::size_t t = 0; t < tiles.size(); ++t) compose_.clear(slot_of(t), tiles[t].width, tiles[t].height);
  int last_guide_renewal = 0;  // the last sample of the render whose world guide is renewed
  for (int s = 1; s < samples; s *= 2) last_guide_renewal = s;
  SampleSchedule schedule(settings);
  int samples_done = samples;
  for (int s = 0; s < samples; ++s) {
    const glm::vec2 u = s == 0 ? glm::vec2(0.5f) : r2_point(static_cast<uint32_t>(s), jitter_rotation);
    const glm::vec2 jitter = (u - 0.5f) * settings.filter_width;
    const Tile frame_tile{x0, y0, x1 - x0, y1 - y0};
    // The guide learns from view probes of its own before the sample draws its directions (so sample 0 is guided
    // too): it does not depend on the directions it guides, which keeps them unbiased.
    if (s == 0) world_reach_.reset();
    const bool guided = plan.guide_world && scene_lights_.world_lights(scene_, settings);
    if (guided && s <= last_guide_renewal) {  // what later samples learn, no table of this render would use
      StageScope scope(timer_, Stage::WorldGuide);
      const uint32_t key = hash_combine(hash_combine(seed, static_cast<uint32_t>(s)), 0x5752u);
      world_reach_.learn(cpu_scene_, cpu::camera_probes(view_projection_of(frame_tile, jitter), cpu_scene_, key),
                         plan.direct == FramePlan::Direct::ShadowMaps, key);
    }
    // Its table changes only at samples 0, 1, 2, 4, 8, ... (the doubling iterations of Müller et al. 2017): the
    // samples in between draw consecutive points of one R2 sequence through the same table, stratified together.
    // (Changed every sample, the sunlit room under its sun and sky had its first bounce's spread over seeds 0-5
    // at 16 samples grow from 0.153 of Cycles' unguided to 0.264.)
    if (renews_world_guide(s)) scene_lights_.guide_world(guided ? world_reach_.reach() : std::span<const float>{});
    const std::vector<BounceLight>& lights = scene_lights_.sample(scene_, settings, static_cast<uint32_t>(s), seed);
    bind_emitter_occluders(scene_lights_.emitter_occluders());
    const RenderContext frame_context = context_of(frame_tile, static_cast<uint32_t>(s), jitter, lights);
    if (flc) {
      if (callbacks.cancelled()) return false;
      flc_.generate(frame_context, plan.vpl_candidates);
      if (traced_direct)
        flc_.add_traced_light(frame_context, cpu_scene_, scene_lights_,
                              flc_visibility ? &topology_visibility_ : nullptr);
      else
        direct_.for_each_shadowed_light(frame_context, shadows_, [&] { flc_.add_light(frame_context); });
      vpl_count = flc_.vpl_count();
      divergent_count = flc_.divergent_count();
    }
    if (ssvp) {
      if (callbacks.cancelled()) return false;
      ssvp_.generate(frame_context, gbuffer_, plan.vpl_importance ? &cpu_scene_ : nullptr, scene_lights_);
      vpl_count = ssvp_.vpl_count();
      cluster_count = ssvp_.cluster_count();
      const bool lamp = ssvp_.main_light() >= 0 && std::size_t(ssvp_.main_light()) < scene_lights_.lamp_count();
      main_light = lamp ? static_cast<int>(scene_.lamp_source_index(std::size_t(ssvp_.main_light()))) : -1;
    }
    for (std::size_t t = 0; t < tiles.size(); ++t) {
      if (callbacks.cancelled()) return false;
      const Tile& tile = tiles[t];
      const RenderContext context = context_of(tile, static_cast<uint32_t>(s), jitter, lights);
      if (tiles_take_turns) compose_.clear(0, tile.width, tile.height);
      gbuffer_.execute(context);
      if (traced_direct) {
        TracedDirectPass::NearFieldRays near_field_rays;
        if (plan.near_field == FramePlan::NearField::RayTraced)
          near_field_rays = {near_field_clamp, plan.near_field_bounces >= 2,
                             ssvp ? ssvp_.first_bounce_candidates() : std::span<const cpu::Vpl>{}};
        traced_direct_.execute(context, gbuffer_.gbuffer(), cpu_scene_, scene_lights_, near_field_rays);
      } else {
        direct_.execute(context, gbuffer_.gbuffer(), shadows_);
      }
      ComposePass::Indirect indirect;
      std::optional<RayCheckSettings> checks;
      if (plan.ray_checks > 0.0f) checks.emplace(RayCheckSettings{cpu_scene_, plan.ray_checks});
      if (flc) {
        if (flc_visibility) topology_visibility_.execute(context, gbuffer_.gbuffer());
        flc_.shade(context, gbuffer_.gbuffer(), flc_visibility ? &topology_visibility_ : nullptr, checks);
        if (flc_.active()) indirect = {flc_.indirect(), false, flc_.levels(), 0};
      }
      if (ssvp) {
        ssvp_.shade(context, gbuffer_.gbuffer(), checks);
        if (ssvp_.active()) indirect = {ssvp_.indirect(), true, ssvp_.debug(), ssvp_.second()};
      }
      const GLuint direct = traced_direct ? traced_direct_.output() : direct_.output();
      if (indirect.light != 0 && plan.near_field == FramePlan::NearField::RayTraced) {
        indirect.near_field =
            near_field_.smoothed(context, gbuffer_.gbuffer(), traced_direct_.near_field(), plan.near_field_blur);
        if (plan.near_field_bounces >= 2 && indirect.second_bounce != 0)
          indirect.near_field_second = near_field_.second_bounce(
              context, traced_direct_.near_field_reflectance(), traced_direct_.near_field_source(),
              traced_direct_.near_field_unseen(), indirect.light, indirect.second_bounce, indirect.near_field);
      }
      if (indirect.light != 0 && plan.near_field == FramePlan::NearField::FromGBuffer)
        indirect.near_field =
            near_field_.from_gbuffer(context, gbuffer_.gbuffer(), direct, near_field_clamp, plan.near_field_blur);
      compose_.accumulate(slot_of(t), context, gbuffer_.gbuffer(), direct, indirect);
      gl::check("rendering a sample");
      if (tiles_take_turns) read_tile(*frame, t, samples, s == 0 ? ComposePass::Into::Replace : ComposePass::Into::Add);
      timer_.resolve();
      const int done = s * static_cast<int>(tiles.size()) + static_cast<int>(t) + 1;
      callbacks.progress(s + 1, static_cast<float>(done) / static_cast<float>(total_steps));
    }

    if (!schedule.another_fits(s + 1)) {
      samples_done = s + 1;
      break;
    }
    if (!tiles_take_turns && s + 1 < samples && schedule.publish_due(s + 1)) {
      auto partial = std::make_shared<Frame>();
      // Ray Checks' clamp needs the Indirect pass, and the Second Bounce where the method has one.
      const uint32_t clamped =
          plan.ray_checks > 0.0f ? aov_bits & ((1u << BOUNCE_AOV_INDIRECT) | (1u << BOUNCE_AOV_SECOND_BOUNCE)) : 0u;
      const uint32_t read_back = schedule.partial_aovs(s + 1);
      partial->allocate(frame->width, frame->height, aov_bits & (read_back | clamped));
      read_frame(*partial, s + 1);
      if (plan.ray_checks > 0.0f) {
        partial->clamp_negative_indirect();
        partial->keep(read_back);
      }
      partial->info.nonfinite_pixels = partial->zero_nonfinite();
      if (schedule.published(*partial, s + 1)) {  // meets Noise Target: the render's last frame, every AOV read below
        samples_done = s + 1;
        break;
      }
      finish_info(*partial, s + 1);
      callbacks.publish(partial);
    }
  }
  if (tiles_take_turns)
    frame->scale(float(samples) / float(samples_done));  // the tiles were added in as 1/samples of each sample
  else
    read_frame(*frame, samples_done);
  if (plan.ray_checks > 0.0f) frame->clamp_negative_indirect();
  finish_info(*frame, samples_done);
  frame->info.nonfinite_pixels = frame->zero_nonfinite();
  schedule.fill_noise(*frame, samples_done);
  callbacks.publish(frame);
  return true;
}

}  // namespace bounce
