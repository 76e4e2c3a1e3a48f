#include "surface_samples.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace bounce::topology {
namespace {

// Of the triangle at soup[i], soup[i + 1], soup[i + 2]; 0 when not finite.
double triangle_area(std::span<const glm::vec3> soup, std::size_t i) {
  const double a = 0.5 * glm::length(glm::cross(glm::dvec3(soup[i + 1] - soup[i]), glm::dvec3(soup[i + 2] - soup[i])));
  return std::isfinite(a) ? a : 0.0;
}

}  // namespace

double surface_area(std::span<const glm::vec3> soup) {
  double area = 0.0;
  for (std::size_t i = 0; i + 2 < soup.size(); i += 3) area += triangle_area(soup, i);
  return area;
}

std::vector<SurfaceSample> sample_surfaces(std::span<const glm::vec3> soup, std::size_t count, Draws& draws) {
  std::vector<double> cumulative_area;
  cumulative_area.reserve(soup.size() / 3);
  double area = 0.0;
  for (std::size_t i = 0; i + 2 < soup.size(); i += 3) cumulative_area.push_back(area += triangle_area(soup, i));
  std::vector<SurfaceSample> samples;
  if (!(area > 0.0)) return samples;
  samples.reserve(count);
  for (std::size_t s = 0; s < count; ++s) {
    const std::size_t triangle =
        std::min(std::size_t(std::upper_bound(cumulative_area.begin(), cumulative_area.end(), draws.uniform() * area) -
                             cumulative_area.begin()),
                 cumulative_area.size() - 1);
    const glm::vec3 a = soup[3 * triangle], b = soup[3 * triangle + 1], c = soup[3 * triangle + 2];
    const glm::vec3 cross = glm::cross(b - a, c - a);
    const float length = glm::length(cross);
    // Uniform on the triangle (pbrt-v4's SampleUniformTriangle, square-root form).
    const float root = float(std::sqrt(draws.uniform())), v = float(draws.uniform());
    if (!(length > 0.0f) || !std::isfinite(length)) continue;
    samples.push_back({a + root * (1.0f - v) * (b - a) + root * v * (c - a), cross / length});
  }
  return samples;
}

}  // namespace bounce::topology
