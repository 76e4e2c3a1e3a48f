// Deterministic sample sequences shared by the render passes (host side); tested in tests/native.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

namespace bounce {

// PCG hash (Jarzynski & Olano 2020); the same function as shaders/common/random.glsl.
inline uint32_t pcg_hash(uint32_t v) {
  const uint32_t state = v * 747796405u + 2891336453u;
  const uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

inline uint32_t hash_combine(uint32_t a, uint32_t b) { return pcg_hash(a ^ (b + 0x9e3779b9u + (a << 6) + (a >> 2))); }

inline float hash_to_unit(uint32_t v) { return static_cast<float>(pcg_hash(v) >> 8) * (1.0f / 16777216.0f); }

// In a cumulative table (cdf[0] = 0, cdf[i + 1] - cdf[i] the weight of entry i; at least two values), the index
// i with cdf[i] <= target < cdf[i + 1], among the entries of positive weight.
inline std::size_t find_in_cdf(std::span<const double> cdf, double target) {
  const auto it = std::upper_bound(cdf.begin() + 1, cdf.end(), target);
  std::size_t i = std::size_t(it - cdf.begin()) - 1;
  i = std::min(i, cdf.size() - 2);
  while (i > 0 && cdf[i + 1] == cdf[i]) --i;  // a target on a zero-weight entry's edge takes the one before
  return i;
}

// Roberts' R2 sequence, rotated by `rotation` (Cranley-Patterson), in [0,1)^2. Index 0 with no rotation is
// (0.5, 0.5): a one-sample render samples pixel centres and the light's centre.
inline glm::vec2 r2_point(uint32_t index, glm::vec2 rotation) {
  constexpr double g = 1.32471795724474602596;  // plastic number
  const double x = 0.5 + index / g + rotation.x;
  const double y = 0.5 + index / (g * g) + rotation.y;
  return {static_cast<float>(x - std::floor(x)), static_cast<float>(y - std::floor(y))};
}

// Shirley-Chiu concentric map of the unit square onto the unit disk (area-preserving); (0.5, 0.5) -> centre.
inline glm::vec2 concentric_disk(glm::vec2 u) {
  const glm::vec2 p = 2.0f * u - 1.0f;
  if (p.x == 0.0f && p.y == 0.0f) return {0.0f, 0.0f};
  constexpr float quarter_pi = 0.785398163f;
  float r, phi;
  if (std::abs(p.x) > std::abs(p.y)) {
    r = p.x;
    phi = quarter_pi * (p.y / p.x);
  } else {
    r = p.y;
    phi = 2.0f * quarter_pi - quarter_pi * (p.x / p.y);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

// A uniform point of triangle (a, b, c) from u in [0,1)^2 (area-preserving square-root map).
inline glm::vec3 uniform_triangle_point(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec2 u) {
  const float s = std::sqrt(u.x);
  return (1.0f - s) * a + s * (1.0f - u.y) * b + s * u.y * c;
}

// A unit direction around unit normal n, cosine-distributed (pdf cos / pi), from u1, u2 in [0, 1).
inline glm::vec3 cosine_direction(glm::vec3 n, float u1, float u2) {
  glm::vec3 t = std::abs(n.x) > 0.9f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
  t = glm::normalize(glm::cross(n, t));
  const glm::vec3 b = glm::cross(n, t);
  const float r = std::sqrt(u1), phi = 6.28318530717959f * u2;
  return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0f, 1.0f - u1)) * n);
}

}  // namespace bounce
