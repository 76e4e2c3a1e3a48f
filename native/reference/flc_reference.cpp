#include "reference/flc_reference.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "common/parallel.h"
#include "scene_data.h"

namespace bounce::reference {
namespace {

constexpr float kPi = 3.14159265358979f;
constexpr double kPiD = 3.14159265358979323846;

glm::vec3 load3(const float v[3]) { return {v[0], v[1], v[2]}; }

// splitmix64's finaliser: a bijective 64-bit hash.
uint64_t mix(uint64_t x) {
  x ^= x >> 30;
  x *= 0xBF58476D1CE4E5B9ull;
  x ^= x >> 27;
  x *= 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Counter-based streams, so a value depends only on (seed, what it is for, which item), never on the thread
// or the order in which items are processed.
enum Purpose : uint64_t { kTrianglePoints = 1, kLightSamples = 2, kIrradianceQuery = 3 };

class Rng {
 public:
  Rng(uint64_t seed, uint64_t purpose, uint64_t item) : state_(mix(mix(seed ^ mix(purpose)) ^ item)) {}
  float next() {
    state_ += 0x9E3779B97F4A7C15ull;
    return static_cast<float>(mix(state_) >> 40) * 0x1p-24f;  // [0, 1)
  }

 private:
  uint64_t state_;
};

// The engine's own sanitising (dropped, clamped, orthonormalised): the reference lights what the engine draws.
std::vector<BounceLight> sanitize_lights(const std::vector<BounceLight>& lights) {
  return prepare_lights(static_cast<uint32_t>(lights.size()), lights.data()).lights;
}

float smoothstep(float edge0, float edge1, float x) {
  const float t = std::clamp((x - edge0) / (edge1 - edge0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// lights.glsl, spot_attenuation.
float spot_attenuation(const BounceLight& light, glm::vec3 from_light) {
  const float cos_phi = glm::dot(from_light, -load3(light.axis_z));
  const float cos_half = std::cos(light.spot_half_angle);
  if (cos_phi <= cos_half) return 0.0f;
  const float smooth_width = (1.0f - cos_half) * light.spot_blend;
  const float factor = smooth_width > 0.0f ? smoothstep(0.0f, smooth_width, cos_phi - cos_half) : 1.0f;
  return light.spot_cos_falloff != 0 ? factor * cos_phi : factor;
}

// Shirley and Chiu's concentric map: the unit square onto the unit disk, area-preserving, so strata stay strata.
glm::vec2 concentric_disk(float s, float t) {
  const float a = 2.0f * s - 1.0f, b = 2.0f * t - 1.0f;
  if (a == 0.0f && b == 0.0f) return {0.0f, 0.0f};
  if (std::abs(a) > std::abs(b)) {
    const float phi = kPi / 4 * (b / a);
    return {a * std::cos(phi), a * std::sin(phi)};
  }
  const float phi = kPi / 2 - kPi / 4 * (a / b);
  return {b * std::cos(phi), b * std::sin(phi)};
}

int grid_side(int samples, int dimensions) {
  int k = 1;
  while (dimensions == 2 ? k * k < samples : k * k * k < samples) ++k;
  return k;
}

struct ShadingContext {
  const embree::Scene& bvh;
  float offset;
  int samples;
  Rng& rng;

  // Whether the segment from y (pushed off its surface along n) to `target` is free.
  bool visible(glm::vec3 y, glm::vec3 n, glm::vec3 target) const {
    const glm::vec3 origin = y + n * offset;
    const glm::vec3 to_target = target - origin;
    const float distance = glm::length(to_target);
    if (distance <= offset) return true;
    return !bvh.occluded(origin, to_target / distance, 0.0f, distance - offset);
  }
  bool visible_direction(glm::vec3 y, glm::vec3 n, glm::vec3 dir) const {
    return !bvh.occluded(y + n * offset, dir, 0.0f, std::numeric_limits<float>::infinity());
  }
};

// Point and spot: lights.glsl's unshadowed irradiance I cos / (d^2 + r^2) (times the cone), times the visible
// fraction of the ball of radius r among its points above y's horizon (the GPU's shadow_visibility: the part below
// cannot reach y and carries no information).
glm::vec3 point_irradiance(const BounceLight& light, glm::vec3 y, glm::vec3 n, ShadingContext& context) {
  const glm::vec3 centre = load3(light.position);
  const glm::vec3 to_light = centre - y;
  const float d2 = glm::dot(to_light, to_light);
  const glm::vec3 l = to_light / std::sqrt(std::max(d2, 1e-30f));
  const float r = light.radius;
  float falloff = std::max(glm::dot(n, l), 0.0f) / (d2 + r * r);
  if (light.type == BOUNCE_LIGHT_SPOT) falloff *= spot_attenuation(light, -l);
  const glm::vec3 unshadowed = load3(light.intensity) * falloff;
  if (!(falloff > 0.0f) || !light.cast_shadow) return unshadowed;
  if (r <= 0.0f) return context.visible(y, n, centre) ? unshadowed : glm::vec3(0.0f);
  const int k = grid_side(context.samples, 3);
  int above = 0, seen = 0;
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < k; ++j) {
      for (int m = 0; m < k; ++m) {
        const float u1 = (float(i) + context.rng.next()) / float(k);
        const float u2 = (float(j) + context.rng.next()) / float(k);
        const float u3 = (float(m) + context.rng.next()) / float(k);
        const float cos_theta = 1.0f - 2.0f * u2;
        const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
        const float phi = 2.0f * kPi * u3;
        const glm::vec3 p =
            centre + r * std::cbrt(u1) * glm::vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
        if (glm::dot(n, p - y) <= 0.0f) continue;
        ++above;
        if (context.visible(y, n, p)) ++seen;
      }
    }
  }
  if (above == 0) return context.visible(y, n, centre) ? unshadowed : glm::vec3(0.0f);
  return unshadowed * (float(seen) / float(above));
}

// Sun: E cos toward axis_z, times the visible fraction of its disk (directions uniform in the cone of half the
// angular diameter) among the directions above y's horizon.
glm::vec3 sun_irradiance(const BounceLight& light, glm::vec3 y, glm::vec3 n, ShadingContext& context) {
  const glm::vec3 z = load3(light.axis_z), x = load3(light.axis_x), w = load3(light.axis_y);
  const float cos_n = glm::dot(n, z);
  const glm::vec3 unshadowed = load3(light.intensity) * std::max(cos_n, 0.0f);
  if (!(cos_n > 0.0f) || !light.cast_shadow) return unshadowed;
  const float cos_max = std::cos(0.5f * light.sun_angle);
  if (light.sun_angle <= 0.0f) return context.visible_direction(y, n, z) ? unshadowed : glm::vec3(0.0f);
  const int k = grid_side(context.samples, 2);
  int above = 0, seen = 0;
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < k; ++j) {
      const float cos_theta = 1.0f - (float(i) + context.rng.next()) / float(k) * (1.0f - cos_max);
      const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
      const float phi = 2.0f * kPi * (float(j) + context.rng.next()) / float(k);
      const glm::vec3 dir = glm::normalize(cos_theta * z + sin_theta * (std::cos(phi) * x + std::sin(phi) * w));
      if (glm::dot(n, dir) <= 0.0f) continue;
      ++above;
      if (context.visible_direction(y, n, dir)) ++seen;
    }
  }
  if (above == 0) return context.visible_direction(y, n, z) ? unshadowed : glm::vec3(0.0f);
  return unshadowed * (float(seen) / float(above));
}

// Area: E = L * integral over the emitter of cos_y cos_l / r^2 V dA (stratified points); converges to Lambert's
// polygon formula of lights.glsl where nothing blocks (to the true ellipse, which lights.glsl approximates by
// an equal-area 32-gon). Only the side facing -axis_z emits.
glm::vec3 area_irradiance(const BounceLight& light, glm::vec3 y, glm::vec3 n, ShadingContext& context) {
  const glm::vec3 c = load3(light.position), z = load3(light.axis_z);
  if (glm::dot(y - c, -z) <= 0.0f) return glm::vec3(0.0f);
  const glm::vec3 u = load3(light.axis_x) * light.half_size[0], v = load3(light.axis_y) * light.half_size[1];
  const bool rect = light.type == BOUNCE_LIGHT_AREA_RECT;
  const float area = (rect ? 4.0f : kPi) * light.half_size[0] * light.half_size[1];
  const int k = grid_side(context.samples, 2);
  double sum = 0.0;
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < k; ++j) {
      const float s = (float(i) + context.rng.next()) / float(k);
      const float t = (float(j) + context.rng.next()) / float(k);
      const glm::vec2 q = rect ? glm::vec2(2.0f * s - 1.0f, 2.0f * t - 1.0f) : concentric_disk(s, t);
      const glm::vec3 p = c + q.x * u + q.y * v;
      const glm::vec3 to_p = p - y;
      const float d2 = glm::dot(to_p, to_p);
      if (!(d2 > 0.0f)) continue;
      const float d = std::sqrt(d2);
      const float cos_y = glm::dot(n, to_p) / d;
      const float cos_l = glm::dot(to_p, z) / d;
      if (cos_y <= 0.0f || cos_l <= 0.0f) continue;
      if (light.cast_shadow && !context.visible(y, n, p)) continue;
      sum += double(cos_y) * double(cos_l) / double(d2);
    }
  }
  return load3(light.intensity) * static_cast<float>(sum * double(area) / double(k * k));
}

glm::vec3 irradiance_with(const Scene& scene, glm::vec3 y, glm::vec3 n, const Options& options, Rng& rng) {
  const float offset = options.shadow_offset > 0.0f ? options.shadow_offset : 1e-4f * scene.diagonal();
  ShadingContext context{scene.bvh(), offset, std::max(options.light_samples, 1), rng};
  glm::vec3 sum(0.0f);
  for (const BounceLight& light : scene.lights()) {
    switch (light.type) {
      case BOUNCE_LIGHT_POINT:
      case BOUNCE_LIGHT_SPOT:
        sum += point_irradiance(light, y, n, context);
        break;
      case BOUNCE_LIGHT_SUN:
        sum += sun_irradiance(light, y, n, context);
        break;
      default:
        sum += area_irradiance(light, y, n, context);
        break;
    }
  }
  return sum;
}

}  // namespace

Scene::Scene(std::vector<Triangle> triangles, std::vector<BounceLight> lights)
    : triangles_(std::move(triangles)), lights_(sanitize_lights(lights)) {
  std::vector<glm::vec3> soup;
  soup.reserve(3 * triangles_.size());
  for (const Triangle& t : triangles_) soup.insert(soup.end(), t.p.begin(), t.p.end());
  bvh_.add_triangles(soup);
  bvh_.commit();
}

float Scene::diagonal() const {
  if (triangles_.empty()) return 0.0f;
  return glm::length(bounds_max() - bounds_min());
}

glm::vec3 irradiance(const Scene& scene, glm::vec3 y, glm::vec3 n, const Options& options) {
  // Seeded by the query itself, so separate queries do not share one stratification pattern.
  uint64_t item = 0;
  for (float f : {y.x, y.y, y.z, n.x, n.y, n.z}) item = mix(item ^ std::bit_cast<uint32_t>(f));
  Rng rng(options.seed, kIrradianceQuery, item);
  return irradiance_with(scene, y, n, options, rng);
}

std::vector<Vpl> make_vpls(const Scene& scene, Mode mode, const Options& options) {
  const std::vector<Triangle>& triangles = scene.triangles();
  // Points per triangle first, so every point has a fixed index whatever the threads do.
  std::vector<std::size_t> first(triangles.size() + 1, 0);
  std::vector<int> side(triangles.size(), 0);  // m: the triangle is cut into m^2 sub-triangles
  std::vector<glm::vec3> normals(triangles.size());
  std::vector<float> areas(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const auto& p = triangles[i].p;
    const glm::vec3 cross = glm::cross(p[1] - p[0], p[2] - p[0]);
    const float length = glm::length(cross);
    areas[i] = 0.5f * length;
    normals[i] = cross / length;
    const bool usable = std::isfinite(length) && length > 0.0f && std::isfinite(normals[i].x) &&
                        std::isfinite(normals[i].y) && std::isfinite(normals[i].z);
    if (usable) {
      if (mode == Mode::many_lights) {
        side[i] = 1;
      } else {
        const double wanted = std::max(double(options.min_points_per_triangle),
                                       std::ceil(double(areas[i]) * double(options.points_per_unit_area)));
        side[i] = std::max(1, static_cast<int>(std::ceil(std::sqrt(std::min(wanted, 1e12)) - 1e-9)));
      }
    }
    first[i + 1] = first[i] + std::size_t(side[i]) * std::size_t(side[i]);
  }
  std::vector<Vpl> vpls(first.back());
  parallel_for(triangles.size(), options.threads, 16, [&](std::size_t i) {
    const int m = side[i];
    if (m == 0) return;
    const auto& p = triangles[i].p;
    const glm::vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
    Rng position_rng(options.seed, kTrianglePoints, i);
    std::size_t index = first[i];
    auto emit = [&](glm::vec3 position) {
      Vpl& vpl = vpls[index];
      vpl.position = position;
      vpl.normal = normals[i];
      vpl.albedo = triangles[i].albedo;
      vpl.area = areas[i] / float(m * m);
      Rng light_rng(options.seed, kLightSamples, index);
      vpl.irradiance_front = irradiance_with(scene, position, normals[i], options, light_rng);
      vpl.irradiance_back = irradiance_with(scene, position, -normals[i], options, light_rng);
      ++index;
    };
    if (mode == Mode::many_lights) {
      emit((p[0] + p[1] + p[2]) / 3.0f);
      return;
    }
    // Sub-triangle corners in the (e1, e2) coordinates, in units of 1/m: "up" (a, b), (a+1, b), (a, b+1) for
    // a + b <= m - 1 and "down" (a+1, b), (a, b+1), (a+1, b+1) for a + b <= m - 2: m^2 congruent triangles.
    for (int a = 0; a < m; ++a) {
      for (int b = 0; a + b < m; ++b) {
        for (int down = 0; down < 2; ++down) {
          if (down && a + b > m - 2) continue;
          const glm::vec2 q0 = down ? glm::vec2(a + 1, b) : glm::vec2(a, b);
          const glm::vec2 q1 = down ? glm::vec2(a, b + 1) : glm::vec2(a + 1, b);
          const glm::vec2 q2 = down ? glm::vec2(a + 1, b + 1) : glm::vec2(a, b + 1);
          const float r = std::sqrt(position_rng.next());
          const float s = position_rng.next();
          const glm::vec2 q = ((1.0f - r) * q0 + r * (1.0f - s) * q1 + r * s * q2) / float(m);
          emit(p[0] + q.x * e1 + q.y * e2);
        }
      }
    }
  });
  return vpls;
}

glm::vec3 vpl_radiance(const Vpl& vpl, glm::vec3 x) {
  const glm::vec3 to_x = x - vpl.position;
  const float distance = glm::length(to_x);
  if (!(distance > 0.0f)) return glm::vec3(0.0f);
  const float cos_side = glm::dot(vpl.normal, to_x) / distance;
  const glm::vec3 e = cos_side >= 0.0f ? vpl.irradiance_front : vpl.irradiance_back;
  return vpl.albedo * e * (3.0f / (2.0f * kPi)) * std::abs(cos_side);  // Eq. 6, on the side facing x
}

glm::vec3 transfer(const Vpl& vpl, const Receiver& receiver, float epsilon) {
  const glm::vec3 to_x = receiver.position - vpl.position;
  const float distance = glm::length(to_x);
  if (!(distance > 0.0f)) return glm::vec3(0.0f);  // no direction: the light is on the receiver
  const glm::vec3 dir = to_x / distance;
  const float cos_x = std::max(0.0f, -glm::dot(receiver.normal, dir));
  if (cos_x == 0.0f) return glm::vec3(0.0f);
  const float cos_y = std::abs(glm::dot(vpl.normal, dir));  // <n_i, y x>^+ of the side facing x
  const float d = std::max(epsilon, distance);
  return vpl_radiance(vpl, receiver.position) * receiver.albedo * (cos_x * cos_y / (kPi * d * d));  // Eq. 5
}

glm::vec3 gather(std::span<const Vpl> vpls, const Receiver& receiver, float epsilon) {
  glm::dvec3 sum(0.0);
  for (const Vpl& vpl : vpls) sum += glm::dvec3(transfer(vpl, receiver, epsilon)) * double(vpl.area);  // Eq. 4
  return glm::vec3(sum);
}

std::vector<glm::vec3> indirect(const Scene& scene, std::span<const Receiver> receivers, Mode mode,
                                const Options& options) {
  const std::vector<Vpl> vpls = make_vpls(scene, mode, options);
  std::vector<glm::vec3> out(receivers.size());
  parallel_for(receivers.size(), options.threads, 1,
               [&](std::size_t i) { out[i] = gather(vpls, receivers[i], options.epsilon); });
  return out;
}

std::vector<glm::vec3> many_lights(const Scene& scene, std::span<const Receiver> receivers, const Options& options) {
  return indirect(scene, receivers, Mode::many_lights, options);
}

std::vector<glm::vec3> continuous(const Scene& scene, std::span<const Receiver> receivers, const Options& options) {
  return indirect(scene, receivers, Mode::continuous, options);
}

Image render(const Scene& scene, const BounceCamera& camera, Mode mode, const Options& options) {
  if (camera.width <= 0 || camera.height <= 0) throw std::invalid_argument("render: empty image");
  glm::dmat4 view(1.0), projection(1.0);
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      view[c][r] = camera.world_to_view[4 * c + r];
      projection[c][r] = camera.projection[4 * c + r];
    }
  }
  const glm::dmat4 clip_to_world = glm::inverse(projection * view);
  const std::vector<Vpl> vpls = make_vpls(scene, mode, options);
  const int width = camera.width, height = camera.height;
  const std::size_t pixels = std::size_t(width) * std::size_t(height);
  Image image{width, height, std::vector<glm::vec3>(pixels), std::vector<glm::vec3>(pixels),
              std::vector<uint8_t>(pixels)};
  parallel_for(std::size_t(height), options.threads, 1, [&](std::size_t row) {
    for (int column = 0; column < width; ++column) {
      const double ndc_x = (column + 0.5) / width * 2.0 - 1.0;
      const double ndc_y = (double(row) + 0.5) / height * 2.0 - 1.0;
      const glm::dvec4 near = clip_to_world * glm::dvec4(ndc_x, ndc_y, -1.0, 1.0);
      const glm::dvec4 far = clip_to_world * glm::dvec4(ndc_x, ndc_y, 1.0, 1.0);
      const glm::dvec3 origin = glm::dvec3(near) / near.w;
      glm::dvec3 dir;
      double tmax;
      if (std::abs(far.w) > 1e-12 * std::abs(near.w)) {
        dir = glm::dvec3(far) / far.w - origin;
        tmax = glm::length(dir);
      } else {  // an infinite far plane
        dir = glm::dvec3(far);
        tmax = std::numeric_limits<double>::infinity();
      }
      dir = glm::normalize(dir);
      const auto hit = scene.bvh().intersect(glm::vec3(origin), glm::vec3(dir), 0.0f, static_cast<float>(tmax));
      if (!hit) continue;
      const Triangle& triangle = scene.triangles()[hit->prim_id];
      Receiver receiver;
      // On the triangle exactly, from the barycentrics rather than origin + t dir.
      receiver.position = (1.0f - hit->u - hit->v) * triangle.p[0] + hit->u * triangle.p[1] + hit->v * triangle.p[2];
      receiver.normal = glm::dot(hit->normal, glm::vec3(dir)) > 0.0f ? -hit->normal : hit->normal;
      receiver.albedo = glm::vec3(1.0f);
      const std::size_t pixel = row * std::size_t(width) + std::size_t(column);
      image.incident[pixel] = gather(vpls, receiver, options.epsilon);
      image.albedo[pixel] = triangle.albedo;
      image.covered[pixel] = 1;
    }
  });
  return image;
}

}  // namespace bounce::reference
