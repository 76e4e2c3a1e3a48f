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
#include "radiometry.h"
#include "sampling.h"

namespace bounce::cpu {
namespace {

constexpr int kProbes = 1024;               // probe pixels, in a grid of the image's aspect
constexpr int kPathsPerProbe = 2;           // cosine-distributed paths from each probe's surface, two bounces long
constexpr std::size_t kLightsPerClass = 4;  // lights of a class evaluated per vertex; more are drawn uniformly
enum Purpose : uint64_t { kProbe = 31 };

using PerSource = std::array<double, kLightSourceCount>;

struct ProbeResult {
  PerSource direct{};
  std::array<PerSource, kPathsPerProbe> first_bounce{}, second_bounce{};  // per path
  double emission = 0.0, background = 0.0, albedo = 0.0;
  int escaped = 0;
  bool hit = false;

  double direct_total() const { return direct[0] + direct[1] + direct[2]; }
  double first_total(int p) const { return first_bounce[p][0] + first_bounce[p][1] + first_bounce[p][2]; }
  double second_total(int p) const { return second_bounce[p][0] + second_bounce[p][1] + second_bounce[p][2]; }
  double source_total(int c, int p) const { return direct[c] + first_bounce[p][c] + second_bounce[p][c]; }
  double bounces_mean() const {
    double sum = 0.0;
    for (int p = 0; p < kPathsPerProbe; ++p) sum += first_total(p) + second_total(p);
    return sum / kPathsPerProbe;
  }
};

// Error weights (SceneAnalysis) over square blocks of kErrorBlock probes a side: the light a component brings is
// squared as the product of the block's means over two halves of its paths (even and odd), independent, so that
// the paths' noise does not count as light; a bounce's light is smooth at that scale where one probe's two paths
// are too few (a room lit through a doorway: most paths find nothing). The image it is weighed against is each
// probe's own direct light and what it sees, plus its block's mean bounces.
constexpr int kErrorBlock = 4;
static_assert(kPathsPerProbe % 2 == 0, "the error weights need two halves of the paths");

// `of(probe, path)`: the light of a component along a path; the sum over the probes of its error weight.
template <class Of>
double error_weight_sum(const std::vector<ProbeResult>& results, int columns, int rows, Of of) {
  double sum = 0.0;
  for (int by = 0; by < rows; by += kErrorBlock)
    for (int bx = 0; bx < columns; bx += kErrorBlock) {
      const auto each = [&](auto visit) {
        for (int y = by; y < std::min(rows, by + kErrorBlock); ++y)
          for (int x = bx; x < std::min(columns, bx + kErrorBlock); ++x)
            visit(results[std::size_t(y) * std::size_t(columns) + std::size_t(x)]);
      };
      double even = 0.0, odd = 0.0, bounces = 0.0;
      int count = 0;
      each([&](const ProbeResult& r) {
        for (int p = 0; p < kPathsPerProbe; p += 2) {
          even += of(r, p);
          odd += of(r, p + 1);
        }
        bounces += r.bounces_mean();
        ++count;
      });
      const double halves = double(count) * (kPathsPerProbe / 2);
      const double light_squared = (even / halves) * (odd / halves);
      each([&](const ProbeResult& r) {
        const double image = r.direct_total() + r.emission + r.background + bounces / count;
        sum += light_squared / (image * image + 0.01);
      });
    }
  return sum;
}

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
      for (int c = 0; c < kLightSourceCount; ++c) r.first_bounce[p][c] = luminance(x.albedo * y->albedo * ey[c] / kPi);
      const auto z = bounce_from(*y, rng);
      if (!z) continue;
      const auto ez = irradiance(z->position, z->shading_normal, rng);
      for (int c = 0; c < kLightSourceCount; ++c)
        r.second_bounce[p][c] = luminance(x.albedo * y->albedo * z->albedo * ez[c] / kPi);
    }
  });

  SceneAnalysis analysis;
  int paths = 0, escaped = 0;
  for (const ProbeResult& r : results) {
    for (int c = 0; c < kLightSourceCount; ++c) {
      analysis.direct[c] += r.direct[c];
      for (int p = 0; p < kPathsPerProbe; ++p) analysis.first_bounce[c] += r.first_bounce[p][c] / kPathsPerProbe;
    }
    for (int p = 0; p < kPathsPerProbe; ++p) analysis.second_bounce += r.second_total(p) / kPathsPerProbe;
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
  const auto error_weight = [&](auto of) { return error_weight_sum(results, columns, rows, of) / n; };
  for (int c = 0; c < kLightSourceCount; ++c) {
    analysis.direct[c] /= n;
    analysis.first_bounce[c] /= n;
    analysis.error_weight_source[c] = error_weight([c](const ProbeResult& r, int p) { return r.source_total(c, p); });
  }
  analysis.error_weight_first = error_weight([](const ProbeResult& r, int p) { return r.first_total(p); });
  analysis.error_weight_second = error_weight([](const ProbeResult& r, int p) { return r.second_total(p); });
  analysis.error_weight_bounces =
      error_weight([](const ProbeResult& r, int p) { return r.first_total(p) + r.second_total(p); });
  analysis.second_bounce /= n;
  analysis.emission_seen /= n;
  analysis.background_seen /= n;
  analysis.mean_albedo /= std::max(analysis.probes, 1);
  analysis.openness = paths > 0 ? double(escaped) / double(paths) : 1.0;
  analysis.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return analysis;
}

}  // namespace bounce::cpu
