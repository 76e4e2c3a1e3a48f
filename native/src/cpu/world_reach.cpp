#include "cpu/world_reach.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/parallel.h"
#include "cpu/random.h"
#include "radiometry.h"
#include "sampling.h"

namespace bounce::cpu {
namespace {

enum Purpose : uint64_t { kReach = 41 };

// Whether unit direction w from surface point p of unit normal n sees the sky: the cosine it meets the surface
// at, or 0 behind the surface or past an occluder.
float sky_cosine(const CpuScene& scene, glm::vec3 p, glm::vec3 n, glm::vec3 w, float offset) {
  const float cosine = glm::dot(n, w);
  if (!(cosine > 0.0f)) return 0.0f;
  return scene.occluded(p + n * offset, w, 0.0f, std::numeric_limits<float>::infinity()) ? 0.0f : cosine;
}

}  // namespace

void WorldReach::reset() {
  sum_.assign(sphere_bins::kCount, 0.0);
  mean_.clear();
  probes_learned_ = 0;
}

void WorldReach::learn(const CpuScene& scene, std::span<const ViewProbe> probes, bool direct, uint32_t key) {
  if (sum_.size() != std::size_t(sphere_bins::kCount)) reset();
  if (probes.empty()) return;
  const float offset = scene.ray_offset();
  // Per probe and bin: albedo / pi x (direct: cos V at the probe; bounce: the mean over its paths of albedo x
  // cos V where they land). A cosine-distributed path's landing point y stands for the bounce's integral
  // E(x) = pi x mean(albedo(y) / pi x E_sun(y)), so the probe's radiance is albedo(x) / pi x that.
  std::vector<float> reach(probes.size() * std::size_t(sphere_bins::kCount), 0.0f);
  parallel_for(probes.size(), 0, 1, [&](std::size_t i) {
    const ViewProbe& probe = probes[i];
    Rng rng(key, kReach, i);
    struct Landing {
      glm::vec3 position, normal, albedo;
    };
    std::vector<Landing> landings;
    for (int k = 0; k < kPathsPerProbe; ++k) {
      const float u1 = rng.next(), u2 = rng.next();
      const glm::vec3 d = cosine_direction(probe.normal, u1, u2);
      const auto hit =
          scene.intersect(probe.position + probe.normal * offset, d, 0.0f, std::numeric_limits<float>::infinity());
      if (!hit) continue;
      const Surface s = scene.surface(*hit, d);
      if (luminance(s.albedo) > 0.0f) landings.push_back({s.position, s.shading_normal, s.albedo});
    }
    const float albedo = luminance(probe.albedo) / kPi;
    if (!(albedo > 0.0f)) return;
    for (int b = 0; b < sphere_bins::kCount; ++b) {
      const glm::vec3 w = sphere_bins::direction(b, {rng.next(), rng.next()});
      float light = direct ? sky_cosine(scene, probe.position, probe.normal, w, offset) : 0.0f;
      float bounced = 0.0f;
      for (const Landing& y : landings)
        bounced += luminance(y.albedo) * sky_cosine(scene, y.position, y.normal, w, offset);
      light += bounced / float(kPathsPerProbe);
      reach[i * std::size_t(sphere_bins::kCount) + std::size_t(b)] = albedo * light;
    }
  });
  for (std::size_t i = 0; i < probes.size(); ++i)
    for (std::size_t b = 0; b < sum_.size(); ++b) sum_[b] += double(reach[i * sum_.size() + b]);
  probes_learned_ += probes.size();
  mean_.resize(sum_.size());
  for (std::size_t b = 0; b < sum_.size(); ++b) mean_[b] = float(sum_[b] / double(probes_learned_));
  if (!std::any_of(mean_.begin(), mean_.end(), [](float r) { return r > 0.0f; })) mean_.clear();
}

std::span<const float> WorldReach::reach() const { return mean_; }

}  // namespace bounce::cpu
