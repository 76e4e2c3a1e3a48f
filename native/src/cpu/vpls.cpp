#include "cpu/vpls.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "common/parallel.h"
#include "cpu/direct_light.h"
#include "cpu/random.h"
#include "radiometry.h"
#include "sampling.h"
#include "scene_data.h"

namespace bounce::cpu {
namespace {

enum Purpose : uint64_t { kVplPaths = 11, kWorldPathDirections = 12 };

glm::vec3 sphere_direction(float u1, float u2) {
  const float z = 1.0f - 2.0f * u1, r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 2.0f * kPi * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

float spot_solid_angle(const BounceLight& light) { return 2.0f * kPi * (1.0f - std::cos(light.spot_half_angle)); }

struct Emission {
  glm::vec3 origin, direction, power;  // power: the light's, weighted for this direction's density
};

// One emitted ray whose power, averaged over (u1..u4), is the light's power; `offset` as CpuScene::ray_offset.
Emission emit(const BounceLight& light, glm::vec3 centre, float scene_radius, float offset, float u1, float u2,
              float u3, float u4) {
  const glm::vec3 power = light_power(light, scene_radius);
  const glm::vec3 x = glm::make_vec3(light.axis_x), y = glm::make_vec3(light.axis_y), z = glm::make_vec3(light.axis_z);
  switch (light.type) {
    case BOUNCE_LIGHT_POINT:
      return {glm::make_vec3(light.position), sphere_direction(u1, u2), power};
    case BOUNCE_LIGHT_SPOT: {  // uniform in the cone: its power times the attenuation toward d
      const float cos_half = std::cos(light.spot_half_angle);
      const float cos_theta = 1.0f - u1 * (1.0f - cos_half), sin_theta = std::sqrt(1.0f - cos_theta * cos_theta);
      const float phi = 2.0f * kPi * u2;
      const glm::vec3 d = glm::normalize(-z * cos_theta + (x * std::cos(phi) + y * std::sin(phi)) * sin_theta);
      return {glm::make_vec3(light.position), d, power * spot_attenuation(light, d)};
    }
    case BOUNCE_LIGHT_SUN: {  // uniform over the disk of the scene's radius facing the sun
      const float r = scene_radius * std::sqrt(u1), phi = 2.0f * kPi * u2;
      const glm::vec3 origin = centre + z * (2.0f * scene_radius) + r * (std::cos(phi) * x + std::sin(phi) * y);
      return {origin, -z, power};
    }
    case BOUNCE_LIGHT_AREA_TRIANGLE: {  // uniform over the triangle and its two sides, cosine-weighted
      // The triangle is a surface of the scene too: the ray leaves from just off the side it emits from, or it
      // would hit its own (black) emitter first.
      const auto corners = triangle_light_corners(light);
      const bool back = u1 >= 0.5f;
      const float side_u1 = back ? 2.0f * u1 - 1.0f : 2.0f * u1;
      const glm::vec3 side = back ? -z : z;
      return {uniform_triangle_point(corners[0], corners[1], corners[2], {u3, u4}) + side * offset,
              cosine_direction(side, side_u1, u2), power};
    }
    default: {  // uniform over the emitter, cosine-weighted around -axis_z
      const glm::vec2 q = light.type == BOUNCE_LIGHT_AREA_ELLIPSE ? concentric_disk({u3, u4})
                                                                  : glm::vec2(2.0f * u3 - 1.0f, 2.0f * u4 - 1.0f);
      const glm::vec3 origin =
          glm::make_vec3(light.position) + q.x * light.half_size[0] * x + q.y * light.half_size[1] * y;
      return {origin, cosine_direction(-z, u1, u2), power};
    }
  }
}

float weight(glm::vec3 power) { return std::max(0.0f, power.r + power.g + power.b); }

}  // namespace

glm::vec3 light_power(const BounceLight& light, float scene_radius) {
  const glm::vec3 intensity = glm::make_vec3(light.intensity);
  switch (light.type) {
    case BOUNCE_LIGHT_POINT:
      return intensity * 4.0f * kPi;
    case BOUNCE_LIGHT_SPOT:
      return intensity * spot_solid_angle(light);  // an upper bound: the blend and cos falloff are left out
    case BOUNCE_LIGHT_SUN:
      return intensity * kPi * scene_radius * scene_radius;
    default:
      return intensity * kPi * emitting_area(light);
  }
}

void EmissionGuide::learn(glm::vec2 emission, float importance) {
  if (!(importance > 0.0f) || !std::isfinite(importance)) return;
  const auto cell = [](float u) { return std::clamp(int(u * float(kCellsPerSide)), 0, kCellsPerSide - 1); };
  learned_[std::size_t(cell(emission.y) * kCellsPerSide + cell(emission.x))] += double(importance);
}

void EmissionGuide::update() {
  double total = 0.0;
  for (double value : learned_) total += value;
  cdf_.clear();
  if (!(total > 0.0)) return;
  const double uniform = kUniformShare / double(learned_.size());
  cdf_.push_back(0.0);
  for (double value : learned_) cdf_.push_back(cdf_.back() + (1.0 - kUniformShare) * value / total + uniform);
}

EmissionGuide::Sample EmissionGuide::sample(float pick, glm::vec2 within) const {
  if (cdf_.empty()) return {within, 1.0f};
  const std::size_t k = find_in_cdf(cdf_, double(pick) * cdf_.back());
  const double probability = (cdf_[k + 1] - cdf_[k]) / cdf_.back();
  const glm::vec2 corner(float(k % kCellsPerSide), float(k / kCellsPerSide));
  const glm::vec2 emission = glm::min((corner + within) / float(kCellsPerSide), glm::vec2(1.0f - 1e-7f));
  return {emission, float(probability * double(learned_.size()))};
}

LandingGuide::LandingGuide(glm::vec3 lo, glm::vec3 hi) : grid_(lo, hi, kCellsPerSide) {
  learned_.assign(grid_.size(), 0.0);
}

void LandingGuide::learn(std::span<const Vpl> candidates, std::span<const float> importance, LightKinds kinds) {
  if (learned_.empty()) return;
  for_each_path(candidates, importance, [&](const Vpl& first, double path) {
    if (first.light < kinds.lamps || first.light - kinds.lamps >= kinds.world || first.bounce != 1 || !(path > 0.0))
      return;
    const std::size_t cell = grid_.index_of(first.position);
    if (cell < learned_.size()) learned_[cell] += path;
  });
}

void LandingGuide::update() {
  double total = 0.0;
  for (double value : learned_) total += value;
  cdf_.clear();
  if (!(total > 0.0)) return;
  cdf_.push_back(0.0);
  for (double value : learned_) cdf_.push_back(cdf_.back() + value / total);
}

LandingGuide::Origin LandingGuide::origin(glm::vec3 uniform_origin, glm::vec3 disk_centre, glm::vec3 direction,
                                          float radius, float choice, float pick, glm::vec3 within) const {
  if (uniform()) return {uniform_origin, 1.0f};
  glm::vec3 point = uniform_origin;
  if (choice >= float(kUniformShare)) {
    const std::size_t k = find_in_cdf(cdf_, double(pick) * cdf_.back());
    const glm::vec3 target = grid_.lo + (glm::vec3(grid_.cell(k)) + within) * grid_.cell_size;
    point = target + direction * glm::dot(disk_centre - target, direction);
    if (glm::length(point - disk_centre) > radius) return {point, 0.0f};
  }
  return {point, density(point, direction, kPi * radius * radius)};
}

float LandingGuide::density(glm::vec3 origin, glm::vec3 direction, float disk_area) const {
  if (uniform()) return 1.0f;
  // The line's span inside the grid (slabs), then its cells in order (Amanatides and Woo 1987).
  const glm::vec3 lo = grid_.lo, hi = grid_.lo + glm::vec3(grid_.cells) * grid_.cell_size;
  double t_in = -std::numeric_limits<double>::infinity(), t_out = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (direction[a] == 0.0f) {
      if (origin[a] < lo[a] || origin[a] > hi[a]) return float(kUniformShare);
      continue;
    }
    const double t0 = (double(lo[a]) - origin[a]) / direction[a], t1 = (double(hi[a]) - origin[a]) / direction[a];
    t_in = std::max(t_in, std::min(t0, t1));
    t_out = std::min(t_out, std::max(t0, t1));
  }
  double along = 0.0;  // the sum of probability times length over the cells crossed
  if (t_in < t_out) {
    const glm::dvec3 start = glm::dvec3(origin) + 0.5 * (t_in + std::min(t_out, t_in + 1e-9)) * glm::dvec3(direction);
    glm::ivec3 cell = grid_.cell(grid_.index_of(glm::vec3(start)));
    glm::dvec3 t_next, t_step;
    glm::ivec3 step;
    for (int a = 0; a < 3; ++a) {
      step[a] = direction[a] > 0.0f ? 1 : -1;
      const double boundary = double(lo[a]) + double(cell[a] + (step[a] > 0 ? 1 : 0)) * double(grid_.cell_size[a]);
      t_next[a] =
          direction[a] != 0.0f ? (boundary - origin[a]) / direction[a] : std::numeric_limits<double>::infinity();
      t_step[a] = direction[a] != 0.0f ? double(grid_.cell_size[a]) / std::abs(double(direction[a]))
                                       : std::numeric_limits<double>::infinity();
    }
    double t = t_in;
    while (t < t_out) {
      const int a = t_next.x <= t_next.y ? (t_next.x <= t_next.z ? 0 : 2) : (t_next.y <= t_next.z ? 1 : 2);
      const double end = std::min(t_next[a], t_out);
      const std::size_t k = grid_.index(cell);
      along += (cdf_[k + 1] - cdf_[k]) * std::max(end - t, 0.0);
      t = end;
      cell[a] += step[a];
      if (cell[a] < 0 || cell[a] >= grid_.cells[a]) break;
      t_next[a] += t_step[a];
    }
  }
  const double volume = double(grid_.cell_size.x) * double(grid_.cell_size.y) * double(grid_.cell_size.z);
  return float(kUniformShare + (1.0 - kUniformShare) * double(disk_area) * along / volume);
}

std::vector<uint32_t> light_of_paths(std::span<const double> weights, int paths) {
  std::vector<double> cumulative(weights.size() + 1, 0.0);
  for (std::size_t l = 0; l < weights.size(); ++l)
    cumulative[l + 1] = cumulative[l] + (std::isfinite(weights[l]) ? std::max(weights[l], 0.0) : 0.0);
  if (!(cumulative.back() > 0.0) || paths <= 0) return {};
  std::vector<uint32_t> light_of(static_cast<std::size_t>(paths));
  for (int i = 0; i < paths; ++i)
    light_of[std::size_t(i)] = uint32_t(find_in_cdf(cumulative, (i + 0.5) / paths * cumulative.back()));
  return light_of;
}

std::vector<Vpl> trace_vpls(const CpuScene& scene, std::span<const BounceLight> lights, const VplOptions& options) {
  const int paths = std::max(options.paths, 0), bounces = std::max(options.bounces, 1);
  const float radius = scene.radius();
  if (lights.empty() || paths == 0 || scene.triangle_count() == 0 || !(radius > 0.0f)) return {};
  std::vector<double> power_weights;
  if (options.path_weights.size() != lights.size())
    for (const BounceLight& light : lights) power_weights.push_back(double(weight(light_power(light, radius))));
  const std::vector<uint32_t> light_of =
      light_of_paths(power_weights.empty() ? options.path_weights : std::span<const double>(power_weights), paths);
  if (light_of.empty()) return {};
  std::vector<uint32_t> paths_of(lights.size(), 0);
  for (uint32_t l : light_of) ++paths_of[l];
  const auto is_world = [&](uint32_t l) {
    return l >= options.kinds.lamps && l - options.kinds.lamps < options.kinds.world;
  };
  // light_of is in the lights' order, so the world's paths are one run: path i is the (i - first_world_path)-th.
  const auto first_world_path =
      std::size_t(std::find_if(light_of.begin(), light_of.end(), is_world) - light_of.begin());
  const auto world_paths = uint32_t(std::count_if(light_of.begin(), light_of.end(), is_world));
  Rng rotation_rng(options.seed, kWorldPathDirections, 0);
  const glm::vec2 world_rotation(rotation_rng.next(), rotation_rng.next());
  const glm::vec3 centre = 0.5f * (scene.bounds_min() + scene.bounds_max());
  const float offset = scene.ray_offset();
  std::vector<std::vector<Vpl>> per_path(static_cast<std::size_t>(paths));
  const auto landing_guided = [&](uint32_t l) {
    return options.world_guide && !options.world_guide->uniform() && is_world(l) && lights[l].type == BOUNCE_LIGHT_SUN;
  };
  parallel_for(std::size_t(paths), 0, 16, [&](std::size_t i) {
    Rng rng(options.seed, kVplPaths, i);
    const uint32_t l = light_of[i];
    const float u1 = rng.next(), u2 = rng.next(), u3 = rng.next(), u4 = rng.next();
    const EmissionGuide::Sample guided = l < options.guides.size() && !options.guides[l].uniform()
                                             ? options.guides[l].sample(rng.next(), {u1, u2})
                                             : EmissionGuide::Sample{{u1, u2}, 1.0f};
    BounceLight light = lights[l];
    float light_paths = float(paths_of[l]);
    if (options.world_table && is_world(l)) {
      // L / p: the world's whole irradiance from this direction, shared by all of the world's paths.
      const auto drawn = options.world_table->draw_world(r2_point(uint32_t(i - first_world_path), world_rotation));
      if (!drawn || !(drawn->pdf > 0.0f)) return;
      light = world_sun(drawn->direction, drawn->radiance / drawn->pdf);
      dim_to_max_intensity(light.intensity);  // the range policy of SceneLights' own world directions
      light_paths = float(world_paths);
    }
    Emission ray = emit(light, centre, radius, offset, guided.emission.x, guided.emission.y, u3, u4);
    float density = guided.density;
    if (landing_guided(l)) {
      // The world's directions are suns: their disks lie 2 radii from the centre, facing them.
      const float choice = rng.next(), pick = rng.next();
      const LandingGuide::Origin guided_origin = options.world_guide->origin(
          ray.origin, centre - 2.0f * radius * ray.direction, ray.direction, radius, choice, pick, {u1, u2, u3});
      if (!(guided_origin.density > 0.0f)) return;  // off the disk, where no light comes from
      ray.origin = guided_origin.point;
      density = guided_origin.density;
    }
    glm::vec3 power = ray.power / (light_paths * density);
    for (int bounce = 1; bounce <= bounces; ++bounce) {
      if (!(weight(power) > 0.0f) || !std::isfinite(weight(power))) break;
      // The origin is already off its surface: a near limit as well would skip an adjoining face within it (the
      // floor of a box seen from next to a corner) and let paths out of closed volumes.
      const auto hit = scene.intersect(ray.origin, ray.direction, 0.0f, std::numeric_limits<float>::infinity());
      if (!hit) break;
      const Surface s = scene.surface(*hit, ray.direction);
      power *= s.albedo;
      if (!(weight(power) > 0.0f)) break;
      per_path[i].push_back({s.position, s.normal, power, uint32_t(bounce), l, guided.emission});
      // Cosine-weighted: the next ray carries the reflected power unchanged (the cosine and pdf cancel).
      ray.origin = s.position + s.normal * offset;
      ray.direction = cosine_direction(s.normal, rng.next(), rng.next());
    }
  });
  std::vector<Vpl> vpls;
  for (const auto& path : per_path) vpls.insert(vpls.end(), path.begin(), path.end());
  return vpls;
}

void PathShares::reset(std::size_t lamps) { second_moment_.assign(lamps + 2, 0.0); }

std::size_t PathShares::class_of(std::size_t light, LightKinds kinds) {
  return light < kinds.lamps ? light : light < kinds.lamps + kinds.world ? kinds.lamps : kinds.lamps + 1;
}

std::vector<double> PathShares::weights(std::span<const BounceLight> lights, LightKinds kinds,
                                        float scene_radius) const {
  if (second_moment_.size() != kinds.lamps + 2) return {};
  std::vector<double> power(lights.size()), class_power(second_moment_.size(), 0.0);
  for (std::size_t l = 0; l < lights.size(); ++l) {
    power[l] = double(weight(light_power(lights[l], scene_radius)));
    if (!std::isfinite(power[l])) return {};
    class_power[class_of(l, kinds)] += power[l];
  }
  double total_power = 0.0, total_root = 0.0;
  for (std::size_t c = 0; c < class_power.size(); ++c) {
    total_power += class_power[c];
    if (class_power[c] > 0.0) total_root += std::sqrt(second_moment_[c]);
  }
  if (!(total_root > 0.0) || !std::isfinite(total_root) || !(total_power > 0.0)) return power;
  std::vector<double> weights(lights.size());
  for (std::size_t l = 0; l < lights.size(); ++l) {
    const std::size_t c = class_of(l, kinds);
    if (!(class_power[c] > 0.0)) continue;
    const double share =
        (1.0 - kPowerShare) * std::sqrt(second_moment_[c]) / total_root + kPowerShare * class_power[c] / total_power;
    weights[l] = share * power[l] / class_power[c];
  }
  return weights;
}

void PathShares::learn(std::span<const Vpl> candidates, std::span<const float> importance,
                       std::span<const double> weights, int paths, LightKinds kinds) {
  if (second_moment_.size() != kinds.lamps + 2) return;
  std::vector<double> class_paths(second_moment_.size(), 0.0), sum_of_squares(second_moment_.size(), 0.0);
  for (uint32_t l : light_of_paths(weights, paths)) class_paths[class_of(l, kinds)] += 1.0;
  for_each_path(candidates, importance,
                [&](const Vpl& first, double path) { sum_of_squares[class_of(first.light, kinds)] += path * path; });
  // Earlier samples count for less: guides learn, and a class's paths grow more useful than its first ones.
  for (std::size_t c = 0; c < second_moment_.size(); ++c)
    second_moment_[c] = kMemory * second_moment_[c] + class_paths[c] * sum_of_squares[c];
}

std::vector<Draw> resample(std::span<const float> importance, int count, float uniform_share, float u) {
  const std::size_t m = importance.size();
  if (m == 0 || count <= 0) return {};
  const auto valid = [&](std::size_t i) { return std::isfinite(importance[i]) ? std::max(importance[i], 0.0f) : 0.0f; };
  double total = 0.0;
  for (std::size_t i = 0; i < m; ++i) total += valid(i);
  const double share = total > 0.0 ? std::clamp(double(uniform_share), 0.0, 1.0) : 1.0;
  const auto probability = [&](std::size_t i) {
    return (1.0 - share) * (total > 0.0 ? valid(i) / total : 0.0) + share / double(m);
  };
  std::size_t last_drawable = m - 1;
  while (last_drawable > 0 && !(probability(last_drawable) > 0.0)) --last_drawable;
  std::vector<Draw> draws;
  draws.reserve(std::size_t(count));
  double cumulative = 0.0;
  std::size_t i = 0;
  for (int next = 0; next < count; ++next) {
    // In double: in float, next + u rounds up to next + 1 for u near 1 (255 + 0.999995 is 256), which carried the
    // last draw past every candidate, onto one that may have no probability (an infinite weight: NaN pixels).
    const double target = double(next) + double(u);
    while (i + 1 < m && cumulative + probability(i) * count <= target) cumulative += probability(i++) * count;
    // What rounding leaves of the cumulative sum short of `count` goes to the last candidate that can be drawn.
    const std::size_t drawn = std::min(i, last_drawable);
    draws.push_back({drawn, float(1.0 / (double(count) * probability(drawn)))});
  }
  return draws;
}

glm::vec3 vpl_irradiance(const Vpl& vpl, glm::vec3 x, glm::vec3 n, float clamp) {
  const glm::vec3 to_x = x - vpl.position;
  const float d2 = glm::dot(to_x, to_x);
  if (!(d2 > 0.0f)) return glm::vec3(0.0f);
  // The cosines times the squared distance, so that no square root is taken.
  const float along_vpl = glm::dot(vpl.normal, to_x), along_x = -glm::dot(n, to_x);
  if (along_vpl <= 0.0f || along_x <= 0.0f) return glm::vec3(0.0f);
  return vpl.power * (along_vpl * along_x / d2 / (kPi * std::max(d2, clamp * clamp)));
}

}  // namespace bounce::cpu
