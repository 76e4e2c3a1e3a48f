#include "cpu/scene_analysis.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "common/parallel.h"
#include "cpu/camera_ray.h"
#include "cpu/direct_light.h"
#include "cpu/random.h"
#include "sampling.h"

namespace bounce::cpu {
namespace {

constexpr float kPi = 3.14159265358979f;
constexpr int kProbes = 1024;               // probe pixels, in a grid of the image's aspect
constexpr int kPathsPerProbe = 2;           // cosine-distributed paths from each probe's surface, two bounces long
constexpr std::size_t kLightsPerClass = 4;  // lights of a class evaluated per vertex; more are drawn uniformly
enum Purpose : uint64_t { kProbe = 31 };

double luminance(glm::vec3 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

struct ProbeResult {
  std::array<double, kLightSourceCount> direct{}, first_bounce{};
  double second_bounce = 0.0, emission = 0.0, background = 0.0, albedo = 0.0;
  int escaped = 0;
  bool hit = false;
};

// Direct irradiance at (y, n) from each source class: every light of a class with at most kLightsPerClass, else
// that many drawn uniformly (with replacement) and scaled, an unbiased estimate with a bounded number of rays.
class SourceIrradiance {
 public:
  SourceIrradiance(const AnalysisLights& lights, const ShadowRays& rays) : rays_(rays) {
    const std::size_t world_end = lights.lamp_count + lights.world_count;
    classes_[0] = lights.lights.subspan(0, lights.lamp_count);
    classes_[1] = lights.lights.subspan(lights.lamp_count, lights.world_count);
    classes_[2] = lights.lights.subspan(world_end);
  }
  std::array<glm::vec3, kLightSourceCount> operator()(glm::vec3 y, glm::vec3 n, Rng& rng) const {
    std::array<glm::vec3, kLightSourceCount> e{};
    for (int c = 0; c < kLightSourceCount; ++c) {
      const std::span<const BounceLight> lights = classes_[c];
      if (lights.size() <= kLightsPerClass) {
        for (const BounceLight& light : lights) e[c] += light_irradiance(light, y, n, rays_, rng);
        continue;
      }
      for (std::size_t k = 0; k < kLightsPerClass; ++k) {
        const std::size_t i = std::min(lights.size() - 1, std::size_t(rng.next() * float(lights.size())));
        e[c] += light_irradiance(lights[i], y, n, rays_, rng);
      }
      e[c] *= float(lights.size()) / float(kLightsPerClass);
    }
    return e;
  }

 private:
  ShadowRays rays_;
  std::array<std::span<const BounceLight>, kLightSourceCount> classes_;
};

}  // namespace

SceneAnalysis analyse_scene(const CpuScene& scene, const AnalysisLights& lights, const AnalysisView& view,
                            const WorldRadiance& world, uint64_t seed) {
  const auto start = std::chrono::steady_clock::now();
  const int columns = std::clamp(int(std::lround(std::sqrt(kProbes * double(view.aspect)))), 1, kProbes);
  const int rows = std::max(1, kProbes / columns);
  const glm::dmat4 clip_to_world = glm::inverse(glm::dmat4(view.projection) * glm::dmat4(view.world_to_view));
  const float offset = scene.ray_offset();
  const SourceIrradiance irradiance(lights, ShadowRays{scene.bvh(), offset, 1, scene.opaque(), 1.0f});
  std::vector<ProbeResult> results(std::size_t(columns) * std::size_t(rows));

  // Leaves surface s along a cosine-distributed direction; the hit's surface, if any.
  const auto bounce_from = [&](const Surface& s, Rng& rng) -> std::optional<Surface> {
    const glm::vec3 dir = cosine_direction(s.normal, rng.next(), rng.next());
    const auto hit = scene.intersect(s.position + s.normal * offset, dir, 0.0f, std::numeric_limits<float>::infinity());
    if (!hit) return std::nullopt;
    return scene.surface(*hit, dir);
  };
  parallel_for(results.size(), 0, 16, [&](std::size_t i) {
    ProbeResult& r = results[i];
    Rng rng(seed, kProbe, i);
    const double ndc_x = (double(i % std::size_t(columns)) + rng.next()) / columns * 2.0 - 1.0;
    const double ndc_y = (double(i / std::size_t(columns)) + rng.next()) / rows * 2.0 - 1.0;
    const CameraRay ray = camera_ray(clip_to_world, ndc_x, ndc_y);
    if (!std::isfinite(ray.origin.x) || !std::isfinite(ray.direction.x)) return;
    const auto hit = scene.intersect(ray.origin, ray.direction, 0.0f, ray.tmax);
    if (!hit) {
      if (view.world_seen) r.background = luminance(world(ray.direction));
      return;
    }
    r.hit = true;
    const Surface x = scene.surface(*hit, ray.direction);
    r.emission = luminance(x.emission);
    r.albedo = luminance(x.albedo);
    // Outgoing radiance is albedo / pi times irradiance; with cosine-distributed directions (pdf cos / pi) a
    // path's estimate of what a bounce brings is albedo times the radiance it finds.
    const auto ex = irradiance(x.position, x.shading_normal, rng);
    for (int c = 0; c < kLightSourceCount; ++c) r.direct[c] = luminance(x.albedo * ex[c] / kPi);
    for (int p = 0; p < kPathsPerProbe; ++p) {
      const auto y = bounce_from(x, rng);
      if (!y) {
        ++r.escaped;
        continue;
      }
      const auto ey = irradiance(y->position, y->shading_normal, rng);
      for (int c = 0; c < kLightSourceCount; ++c)
        r.first_bounce[c] += luminance(x.albedo * y->albedo * ey[c] / kPi) / kPathsPerProbe;
      const auto z = bounce_from(*y, rng);
      if (!z) continue;
      const auto ez = irradiance(z->position, z->shading_normal, rng);
      r.second_bounce += luminance(x.albedo * y->albedo * z->albedo * (ez[0] + ez[1] + ez[2]) / kPi) / kPathsPerProbe;
    }
  });

  SceneAnalysis analysis;
  int paths = 0, escaped = 0;
  for (const ProbeResult& r : results) {
    for (int c = 0; c < kLightSourceCount; ++c) {
      analysis.direct[c] += r.direct[c];
      analysis.first_bounce[c] += r.first_bounce[c];
    }
    analysis.second_bounce += r.second_bounce;
    analysis.emission_seen += r.emission;
    analysis.background_seen += r.background;
    analysis.mean_albedo += r.albedo;
    if (r.hit) {
      ++analysis.probes;
      paths += kPathsPerProbe;
      escaped += r.escaped;
    }
  }
  const double n = double(results.size());
  for (int c = 0; c < kLightSourceCount; ++c) {
    analysis.direct[c] /= n;
    analysis.first_bounce[c] /= n;
  }
  analysis.second_bounce /= n;
  analysis.emission_seen /= n;
  analysis.background_seen /= n;
  analysis.mean_albedo /= std::max(analysis.probes, 1);
  analysis.openness = paths > 0 ? double(escaped) / double(paths) : 1.0;
  analysis.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return analysis;
}

}  // namespace bounce::cpu
