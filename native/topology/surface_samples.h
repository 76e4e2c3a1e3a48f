// Points drawn on a triangle soup by area, with fixed draws: the estimates made from rays once per topology
// (passages.h, occluders.h) are the same on every build of a geometry.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace bounce::topology {

// SplitMix64: a fixed stream per purpose.
struct Draws {
  uint64_t state;
  uint64_t next() {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }
  std::size_t below(std::size_t n) { return std::size_t(uniform() * double(n)) % n; }
};

struct SurfaceSample {
  glm::vec3 position, normal;  // normal: the triangle's unit normal (counter-clockwise front)
};

// The area of the soup's triangles (non-finite ones left out).
double surface_area(std::span<const glm::vec3> soup);

// `count` draws uniform over the soup's area (vertices 3i, 3i + 1, 3i + 2); draws on degenerate or non-finite
// triangles are left out, so fewer may come back. Empty when the soup has no area.
std::vector<SurfaceSample> sample_surfaces(std::span<const glm::vec3> soup, std::size_t count, Draws& draws);

}  // namespace bounce::topology
