// Deterministic sample sequences shared by the render passes (host side); tested in tests/native.
#pragma once

#include <algorithm>
#include <array>
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

// The first three dimensions of Sobol's sequence (direction numbers of Joe and Kuo 2008: the polynomials 1, x + 1
// and x^2 + x + 1), each coordinate Owen-scrambled by its own 32-bit `scramble` (a nested uniform scramble by
// Laine and Karras' hash, Burley, "Practical Hash-based Owen Scrambling", JCGT 2020), in [0,1)^d. The first two are
// a (0,2)-sequence, and scrambling keeps that while making each point uniform: the 2^m points from any multiple of
// 2^m put one point in each elementary interval of area 2^-m, so a penumbra cast by a straight edge, which depends
// on one coordinate of the light, and a bright spot of an environment, which depends on both, are stratified. (A
// rotation instead of the scramble breaks the 2D intervals: on Sponza's HDRI it left 1.5 times the error of a
// rotated R2 sequence, whose 1D projections in turn fill in slowly: 2.5 times Sobol's error in a penumbra.)
namespace detail {
constexpr std::array<std::array<uint32_t, 32>, 3> sobol_directions() {
  std::array<std::array<uint32_t, 32>, 3> v{};
  for (int k = 0; k < 32; ++k) v[0][k] = 1u << (31 - k);
  v[1][0] = 1u << 31;
  for (int k = 1; k < 32; ++k) v[1][k] = v[1][k - 1] ^ (v[1][k - 1] >> 1);
  v[2][0] = 1u << 31;
  v[2][1] = 3u << 30;
  for (int k = 2; k < 32; ++k) v[2][k] = v[2][k - 1] ^ v[2][k - 2] ^ (v[2][k - 2] >> 2);
  return v;
}
inline constexpr auto kSobolDirections = sobol_directions();
inline uint32_t reverse_bits(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}
// Laine and Karras' hash permutes a bit-reversed value so that each bit flips depending on the bits below it:
// reversed back, each bit of the fraction flips depending on the bits above it, Owen's nested scramble.
inline uint32_t nested_uniform_scramble(uint32_t x, uint32_t seed) {
  x = reverse_bits(x) + seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return reverse_bits(x);
}
inline float sobol_coordinate(uint32_t index, int dimension, uint32_t scramble) {
  uint32_t bits = 0;
  for (int k = 0; index != 0; ++k, index >>= 1)
    if (index & 1u) bits ^= kSobolDirections[std::size_t(dimension)][std::size_t(k)];
  return float(nested_uniform_scramble(bits, scramble) >> 8) * 0x1p-24f;
}
}  // namespace detail

inline glm::vec2 sobol_point(uint32_t index, glm::uvec2 scramble) {
  return {detail::sobol_coordinate(index, 0, scramble.x), detail::sobol_coordinate(index, 1, scramble.y)};
}
inline glm::vec3 sobol_point(uint32_t index, glm::uvec3 scramble) {
  return {detail::sobol_coordinate(index, 0, scramble.x), detail::sobol_coordinate(index, 1, scramble.y),
          detail::sobol_coordinate(index, 2, scramble.z)};
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

// Bins of equal solid angle over the unit sphere, for what is learned by direction (cpu::SkyGuide, cpu::WorldReach):
// kRings bands of equal height in z (so of equal solid angle, after Archimedes) by kSectors of azimuth.
namespace sphere_bins {
inline constexpr int kRings = 8, kSectors = 16, kCount = kRings * kSectors;
inline constexpr float kSolidAngle = 4.0f * 3.14159265358979f / float(kCount);

inline int of(glm::vec3 w) {
  const int ring = std::clamp(int((w.z + 1.0f) * 0.5f * float(kRings)), 0, kRings - 1);
  const float turn = std::atan2(w.y, w.x) / 6.28318530717959f + 0.5f;
  const int sector = std::clamp(int(turn * float(kSectors)), 0, kSectors - 1);
  return ring * kSectors + sector;
}

// The unit direction at `within` in [0, 1)^2 of bin `bin`, uniform in solid angle over the bin.
inline glm::vec3 direction(int bin, glm::vec2 within) {
  const int ring = bin / kSectors, sector = bin % kSectors;
  const float z = -1.0f + 2.0f * (float(ring) + within.x) / float(kRings);
  const float phi = ((float(sector) + within.y) / float(kSectors) - 0.5f) * 6.28318530717959f;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}
}  // namespace sphere_bins

}  // namespace bounce
