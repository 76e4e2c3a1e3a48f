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
#include "cpu/direct_light.h"
#include "radiometry.h"
#include "scene_data.h"

namespace bounce::reference {
namespace {

using cpu::mix;
using cpu::Rng;

enum Purpose : uint64_t { kTrianglePoints = 1, kLightSamples = 2, kIrradianceQuery = 3 };

// The engine's own sanitising (dropped, clamped, orthonormalised): the reference lights what the engine draws.
std::vector<BounceLight> sanitize_lights(const std::vector<BounceLight>& lights) {
  return prepare_lights(static_cast<uint32_t>(lights.size()), lights.data()).lights;
}

glm::vec3 irradiance_with(const Scene& scene, glm::vec3 y, glm::vec3 n, const Options& options, Rng& rng) {
  const float offset = options.shadow_offset > 0.0f ? options.shadow_offset : 1e-4f * scene.diagonal();
  return cpu::direct_irradiance(scene.lights(), y, n, {scene.bvh(), offset, options.light_samples}, rng);
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

glm::vec3 vpl_radiance(const Vpl& vpl, glm::vec3 x, bool cosine_lobe) {
  const glm::vec3 to_x = x - vpl.position;
  const float distance = glm::length(to_x);
  if (!(distance > 0.0f)) return glm::vec3(0.0f);
  const float cos_side = glm::dot(vpl.normal, to_x) / distance;
  const glm::vec3 e = cos_side >= 0.0f ? vpl.irradiance_front : vpl.irradiance_back;
  return vpl.albedo * e / kPi * (cosine_lobe ? 1.5f * std::abs(cos_side) : 1.0f);  // on the side facing x
}

glm::vec3 transfer(const Vpl& vpl, const Receiver& receiver, const Options& options) {
  const glm::vec3 to_x = receiver.position - vpl.position;
  const float distance = glm::length(to_x);
  if (!(distance > 0.0f)) return glm::vec3(0.0f);  // no direction: the light is on the receiver
  const glm::vec3 dir = to_x / distance;
  const float cos_x = std::max(0.0f, -glm::dot(receiver.normal, dir));
  if (cos_x == 0.0f) return glm::vec3(0.0f);
  const float cos_y = std::abs(glm::dot(vpl.normal, dir));  // <n_i, y x>^+ of the side facing x
  const float d = std::max(options.epsilon, distance);
  return vpl_radiance(vpl, receiver.position, options.cosine_lobe) * receiver.albedo *
         (cos_x * cos_y / (kPi * d * d));  // Eq. 5
}

glm::vec3 gather(std::span<const Vpl> vpls, const Receiver& receiver, const Options& options) {
  glm::dvec3 sum(0.0);
  for (const Vpl& vpl : vpls) sum += glm::dvec3(transfer(vpl, receiver, options)) * double(vpl.area);  // Eq. 4
  return glm::vec3(sum);
}

std::vector<glm::vec3> indirect(const Scene& scene, std::span<const Receiver> receivers, Mode mode,
                                const Options& options) {
  const std::vector<Vpl> vpls = make_vpls(scene, mode, options);
  std::vector<glm::vec3> out(receivers.size());
  parallel_for(receivers.size(), options.threads, 1,
               [&](std::size_t i) { out[i] = gather(vpls, receivers[i], options); });
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
      image.incident[pixel] = gather(vpls, receiver, options);
      image.albedo[pixel] = triangle.albedo;
      image.covered[pixel] = 1;
    }
  });
  return image;
}

}  // namespace bounce::reference
