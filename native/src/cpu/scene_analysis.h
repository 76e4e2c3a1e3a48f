// What a scene's light is made of, as the camera sees it: the share of the image each light source class gives
// directly and through each bounce, estimated by a small path tracer on Embree (a grid of probe pixels, a few
// cosine-distributed paths from each, shadow rays to a sample of the lights at every vertex). Auto plans from it
// (auto_plan.h) which effects are worth their time.
#pragma once

#include <cstdint>
#include <span>

#include <glm/mat4x4.hpp>

#include "bounce/bounce.h"
#include "cpu/cpu_scene.h"
#include "scene_lights.h"

namespace bounce::cpu {

enum class LightSource { Lamps, World, Emission };
constexpr int kLightSourceCount = 3;

// Mean luminance of the probed pixels, per light path and source class. Units are the image's (radiance).
struct SceneAnalysis {
  double direct[kLightSourceCount] = {};
  double first_bounce[kLightSourceCount] = {};
  double second_bounce = 0.0;  // every source
  double emission_seen = 0.0;  // emissive surfaces the camera sees: in every plan
  double background_seen = 0.0;
  double mean_albedo = 0.0;  // luminance of the albedo at the probes' first hits (what a bounce can add)
  double openness = 0.0;     // of the paths leaving what the camera sees, the share that escapes to the world
  // The relMSE (the benchmarks' measure, mean of (x - r)^2 / (r^2 + 0.01) per pixel) that an error of 100 % in a
  // component would leave: the mean over the probes of its square over the square of the probe's whole image plus
  // 0.01. Unlike a share it weights the dark pixels a bounce alone lights, as relMSE does.
  double error_weight_first = 0.0;                     // every source
  double error_weight_second = 0.0;                    // every source
  double error_weight_bounces = 0.0;                   // both bounces together, every source
  double error_weight_source[kLightSourceCount] = {};  // all of a class's light, direct and bounced
  int probes = 0;                                      // probe pixels that hit a surface
  double milliseconds = 0.0;

  double direct_total() const { return direct[0] + direct[1] + direct[2]; }
  double first_bounce_total() const { return first_bounce[0] + first_bounce[1] + first_bounce[2]; }
  // Everything the image shows.
  double image_total() const {
    return direct_total() + first_bounce_total() + second_bounce + emission_seen + background_seen;
  }
  // A component's share of the image, 0 for a black image.
  double share(double component) const {
    const double total = image_total();
    return total > 0.0 ? component / total : 0.0;
  }
};

struct AnalysisLights {
  std::span<const BounceLight> lights;  // lamps, then the world's directions, then emissive triangles
  std::size_t lamp_count = 0, world_count = 0;
};

struct AnalysisView {
  glm::mat4 world_to_view{1.0f}, projection{1.0f};
  float aspect = 1.0f;     // width over height
  bool world_seen = true;  // the camera sees the world (not transparent nor hidden)
};

// Deterministic for a seed, whatever the threads.
SceneAnalysis analyse_scene(const CpuScene& scene, const AnalysisLights& lights, const AnalysisView& view,
                            const WorldRadiance& world, uint64_t seed);

}  // namespace bounce::cpu
