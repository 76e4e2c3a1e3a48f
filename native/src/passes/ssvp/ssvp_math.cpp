#include "passes/ssvp/ssvp_math.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/type_ptr.hpp>

#include "cpu/vpls.h"
#include "radiometry.h"
#include "scene_data.h"

namespace bounce::ssvp {

namespace {

glm::vec2 wrapped(glm::vec2 u) { return u - glm::floor(u); }

float distance_to(const ClusterPoint& p, const Cluster& c, const ClusterMetric& m) {
  return ssvp_cluster_distance(p.position, p.normal, c.position, c.normal, m.w1, m.w2, m.length_scale);
}

// k-means++: each new centre is a point drawn with probability proportional to its squared distance to the
// nearest centre so far (Arthur and Vassilvitskii 2007), from a hash of `seed`: deterministic.
void add_seeds(std::span<const ClusterPoint> points, std::size_t k, const ClusterMetric& metric, uint32_t seed,
               std::vector<Cluster>& centres) {
  std::vector<float> nearest(points.size(), std::numeric_limits<float>::max());
  auto update = [&](const Cluster& c) {
    for (std::size_t i = 0; i < points.size(); ++i)
      nearest[i] = std::min(nearest[i], distance_to(points[i], c, metric));
  };
  for (const Cluster& c : centres) update(c);
  for (uint32_t draw = 0; centres.size() < k; ++draw) {
    std::size_t chosen = 0;
    if (centres.empty()) {
      chosen = std::min<std::size_t>(static_cast<std::size_t>(hash_to_unit(hash_combine(seed, draw)) * points.size()),
                                     points.size() - 1);
    } else {
      double total = 0.0;
      for (float d : nearest) total += double(d) * d;
      if (!(total > 0.0)) return;  // every point already sits on a centre
      double target = hash_to_unit(hash_combine(seed, draw)) * total;
      for (chosen = 0; chosen + 1 < points.size(); ++chosen) {
        target -= double(nearest[chosen]) * nearest[chosen];
        if (target < 0.0 && nearest[chosen] > 0.0f) break;
      }
      if (!(nearest[chosen] > 0.0f)) return;
    }
    centres.push_back({points[chosen].position, points[chosen].normal, 0});
    update(centres.back());
  }
}

}  // namespace

std::vector<glm::vec2> hammersley_set(uint32_t n, glm::vec2 rotation) {
  std::vector<glm::vec2> set(n);
  for (uint32_t k = 0; k < n; ++k) set[k] = wrapped(ssvp_hammersley(k, n) + rotation);
  return set;
}

std::vector<glm::vec2> disk_set(uint32_t n, glm::vec2 rotation) {
  std::vector<glm::vec2> set = hammersley_set(n, rotation);
  for (glm::vec2& p : set) p = concentric_disk(p);
  return set;
}

float estimated_flux_into_sphere(const BounceLight& light, glm::vec3 centre, float radius) {
  const float power = luminance(glm::make_vec3(light.intensity));
  if (!(power > 0.0f) || !std::isfinite(power)) return 0.0f;
  if (light.type == BOUNCE_LIGHT_SUN) return power * kPi * radius * radius;  // irradiance x cross-section
  const float distance = glm::length(glm::vec3(light.position[0], light.position[1], light.position[2]) - centre);
  // The solid angle of the sphere seen from the light (all of it from inside).
  const float sphere_solid_angle =
      distance <= radius
          ? 4.0f * kPi
          : 2.0f * kPi * (1.0f - std::sqrt(std::max(0.0f, 1.0f - (radius * radius) / (distance * distance))));
  switch (light.type) {
    case BOUNCE_LIGHT_POINT:
      return power * sphere_solid_angle;
    case BOUNCE_LIGHT_SPOT: {
      // A cone that misses the sphere sends nothing into it.
      if (distance > radius) {
        const glm::vec3 axis = -glm::vec3(light.axis_z[0], light.axis_z[1], light.axis_z[2]);
        const glm::vec3 to_centre =
            (centre - glm::vec3(light.position[0], light.position[1], light.position[2])) / distance;
        const float off_axis = std::acos(std::clamp(glm::dot(axis, to_centre), -1.0f, 1.0f));
        if (off_axis - std::asin(radius / distance) > light.spot_half_angle) return 0.0f;
      }
      const float cone = 2.0f * kPi * (1.0f - std::cos(std::min(light.spot_half_angle, kPi)));
      return power * std::min(cone, sphere_solid_angle);
    }
    default: {  // area: radiance x area x pi over its hemisphere
      return power * emitting_area(light) * kPi * std::min(1.0f, sphere_solid_angle / (2.0f * kPi));
    }
  }
}

std::vector<LightDraw> draw_bouncing_lights(std::span<const BounceLight> lights, glm::vec3 centre, float radius,
                                            int count, float u, std::span<const float> flux_factors) {
  std::vector<float> flux(lights.size());
  double total = 0.0;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const float factor = i < flux_factors.size() ? std::max(flux_factors[i], 0.0f) : 1.0f;
    total += flux[i] = estimated_flux_into_sphere(lights[i], centre, radius) * factor;
  }
  std::vector<LightDraw> draws;
  if (!(total > 0.0) || !std::isfinite(total)) return draws;
  // cpu::resample's draws come in index order, each weighted 1 / (count p): a light's m draws add up to m / (count p).
  for (const cpu::Draw& draw : cpu::resample(flux, count, /*uniform_share=*/0.0f, std::clamp(u, 0.0f, 1.0f))) {
    if (draws.empty() || draws.back().index != static_cast<int>(draw.index))
      draws.push_back({static_cast<int>(draw.index), 0, 0.0f});
    ++draws.back().draws;
    draws.back().weight += draw.weight;
  }
  return draws;
}

Clustering cluster_points(std::span<const ClusterPoint> points, int k, const ClusterMetric& metric,
                          std::span<const Cluster> seeds, uint32_t seed, int max_iterations) {
  Clustering result;
  if (points.empty() || k <= 0) return result;
  const std::size_t wanted = std::min<std::size_t>(static_cast<std::size_t>(k), points.size());
  std::vector<Cluster>& centres = result.clusters;
  for (const Cluster& s : seeds)
    if (centres.size() < wanted && std::isfinite(s.position.x + s.position.y + s.position.z)) centres.push_back(s);
  add_seeds(points, wanted, metric, seed, centres);

  result.assignment.assign(points.size(), 0);
  std::vector<float> distance(points.size());
  for (int iteration = 0; iteration < std::max(max_iterations, 1); ++iteration) {
    bool changed = iteration == 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      uint32_t best = 0;
      float best_distance = std::numeric_limits<float>::max();
      for (std::size_t c = 0; c < centres.size(); ++c) {
        const float d = distance_to(points[i], centres[c], metric);
        if (d < best_distance) {
          best_distance = d;
          best = static_cast<uint32_t>(c);
        }
      }
      changed = changed || result.assignment[i] != best;
      result.assignment[i] = best;
      distance[i] = best_distance;
    }
    result.iterations = iteration + 1;
    // Means; an empty cluster takes over the point farthest from its centre (which leaves its old cluster).
    std::vector<glm::dvec3> position_sum(centres.size(), glm::dvec3(0.0)), normal_sum(centres.size(), glm::dvec3(0.0));
    std::vector<uint32_t> count(centres.size(), 0);
    for (std::size_t i = 0; i < points.size(); ++i) {
      position_sum[result.assignment[i]] += glm::dvec3(points[i].position);
      normal_sum[result.assignment[i]] += glm::dvec3(points[i].normal);
      ++count[result.assignment[i]];
    }
    for (std::size_t c = 0; c < centres.size(); ++c) {
      if (count[c] > 0) continue;
      const auto farthest = std::max_element(distance.begin(), distance.end());
      if (!(*farthest > 0.0f)) continue;  // no point off its centre: left empty, dropped below
      const std::size_t i = static_cast<std::size_t>(farthest - distance.begin());
      const uint32_t old = result.assignment[i];
      if (count[old] <= 1) continue;
      position_sum[old] -= glm::dvec3(points[i].position);
      normal_sum[old] -= glm::dvec3(points[i].normal);
      --count[old];
      position_sum[c] = glm::dvec3(points[i].position);
      normal_sum[c] = glm::dvec3(points[i].normal);
      count[c] = 1;
      result.assignment[i] = static_cast<uint32_t>(c);
      distance[i] = 0.0f;
      changed = true;
    }
    for (std::size_t c = 0; c < centres.size(); ++c) {
      centres[c].count = count[c];
      if (count[c] == 0) continue;
      centres[c].position = glm::vec3(position_sum[c] / double(count[c]));
      const double length = glm::length(normal_sum[c]);
      if (length > 1e-6 * count[c]) {
        centres[c].normal = glm::vec3(normal_sum[c] / length);
      } else {  // normals cancel: the member nearest the mean lends its own
        float nearest = std::numeric_limits<float>::max();
        for (std::size_t i = 0; i < points.size(); ++i) {
          if (result.assignment[i] != c) continue;
          const float d = glm::length(points[i].position - centres[c].position);
          if (d < nearest) {
            nearest = d;
            centres[c].normal = points[i].normal;
          }
        }
      }
    }
    if (!changed) break;
  }
  // Drop empty clusters and renumber.
  std::vector<uint32_t> renumber(centres.size(), 0);
  std::vector<Cluster> kept;
  for (std::size_t c = 0; c < centres.size(); ++c) {
    renumber[c] = static_cast<uint32_t>(kept.size());
    if (centres[c].count > 0) kept.push_back(centres[c]);
  }
  for (uint32_t& a : result.assignment) a = renumber[a];
  centres = std::move(kept);
  return result;
}

}  // namespace bounce::ssvp
