#include "voxelize.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "common/parallel.h"

namespace bounce::topology {

namespace {

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool finite_triangle(std::span<const glm::vec3> soup, size_t t) {
  return finite(soup[3 * t]) && finite(soup[3 * t + 1]) && finite(soup[3 * t + 2]);
}

// Separating-axis test of triangle (a, b, c) against the box centred at the origin with half size h on every
// axis: the 3 box axes, the triangle's normal and the 9 edge cross products.
bool triangle_overlaps_box(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, double h) {
  const glm::dvec3 edges[3] = {b - a, c - b, a - c};
  const auto separated = [&](glm::dvec3 axis) {
    const double pa = glm::dot(axis, a), pb = glm::dot(axis, b), pc = glm::dot(axis, c);
    const double r = h * (std::abs(axis.x) + std::abs(axis.y) + std::abs(axis.z));
    return std::min({pa, pb, pc}) > r || std::max({pa, pb, pc}) < -r;
  };
  for (int axis = 0; axis < 3; ++axis) {
    glm::dvec3 unit(0.0);
    unit[axis] = 1.0;
    if (separated(unit)) return false;
    for (const glm::dvec3& e : edges) {
      if (separated(glm::cross(unit, e))) return false;
    }
  }
  return !separated(glm::cross(edges[0], edges[1]));
}

}  // namespace

GridShape fit_grid(std::span<const glm::vec3> soup, int resolution, int margin) {
  GridShape shape;
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (size_t t = 0; t < soup.size() / 3; ++t) {
    if (!finite_triangle(soup, t)) continue;
    for (int k = 0; k < 3; ++k) {
      lo = glm::min(lo, glm::dvec3(soup[3 * t + k]));
      hi = glm::max(hi, glm::dvec3(soup[3 * t + k]));
    }
  }
  if (!(lo.x <= hi.x) || resolution < 1) return shape;
  margin = std::clamp(margin, 0, (resolution - 1) / 2);
  const glm::dvec3 extent = hi - lo;
  const double longest = std::max({extent.x, extent.y, extent.z});
  const int inner = resolution - 2 * margin;
  // A flat or point-like scene still gets a voxel of a size relative to its place, never 0.
  shape.voxel_size = longest > 0.0 ? longest / inner : std::max(1e-6, 1e-6 * glm::length(lo));
  for (int axis = 0; axis < 3; ++axis) {
    const int cells = std::clamp(int(std::ceil(extent[axis] / shape.voxel_size - 1e-9)), 1, inner);
    shape.dims[axis] = cells + 2 * margin;
    // Centre the geometry in its cells.
    const double slack = cells * shape.voxel_size - extent[axis];
    shape.origin[axis] = lo[axis] - slack * 0.5 - margin * shape.voxel_size;
  }
  return shape;
}

VoxelGrid voxelize(std::span<const glm::vec3> soup, const GridShape& shape) {
  VoxelGrid grid{shape, std::vector<uint8_t>(shape.padded_count(), 1)};
  if (shape.empty()) return grid;
  for (int z = 0; z < shape.dims.z; ++z)
    for (int y = 0; y < shape.dims.y; ++y) std::fill_n(&grid.solid[shape.index({0, y, z})], shape.dims.x, 0);

  // Boxes grow by a hair so a triangle lying exactly on a voxel face marks both sides.
  constexpr double kHalf = 0.5 + 1e-6;
  const size_t triangles = soup.size() / 3;
  parallel_for(triangles, 0, 64, [&](size_t t) {
    if (!finite_triangle(soup, t)) return;
    glm::dvec3 p[3];
    for (int k = 0; k < 3; ++k) p[k] = (glm::dvec3(soup[3 * t + k]) - shape.origin) / shape.voxel_size;
    const glm::ivec3 lo = glm::max(glm::ivec3(glm::floor(glm::min(p[0], glm::min(p[1], p[2])) - 1e-6)), glm::ivec3(0));
    const glm::ivec3 hi = glm::min(glm::ivec3(glm::floor(glm::max(p[0], glm::max(p[1], p[2])) + 1e-6)), shape.dims - 1);
    // Walk columns along the normal's dominant axis w; in each, only the cells the plane can reach.
    const glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
    const glm::dvec3 an = glm::abs(n);
    const int w = an.x >= an.y && an.x >= an.z ? 0 : (an.y >= an.z ? 1 : 2);
    const int u = (w + 1) % 3, v = (w + 2) % 3;
    const double plane = glm::dot(n, p[0]);
    const double reach = kHalf * (an.x + an.y + an.z);
    for (int cu = lo[u]; cu <= hi[u]; ++cu) {
      for (int cv = lo[v]; cv <= hi[v]; ++cv) {
        int w0 = lo[w], w1 = hi[w];
        if (an[w] > 0.0) {
          const double rest = plane - n[u] * (cu + 0.5) - n[v] * (cv + 0.5);
          const double a = (rest - reach) / n[w] - 0.5, b = (rest + reach) / n[w] - 0.5;
          w0 = std::max(w0, int(std::floor(std::min(a, b))));
          w1 = std::min(w1, int(std::ceil(std::max(a, b))));
        }
        for (int cw = w0; cw <= w1; ++cw) {
          glm::ivec3 cell;
          cell[u] = cu, cell[v] = cv, cell[w] = cw;
          uint8_t& voxel = grid.solid[shape.index(cell)];
          if (std::atomic_ref<uint8_t>(voxel).load(std::memory_order_relaxed)) continue;
          const glm::dvec3 centre = glm::dvec3(cell) + 0.5;
          if (triangle_overlaps_box(p[0] - centre, p[1] - centre, p[2] - centre, kHalf)) {
            std::atomic_ref<uint8_t>(voxel).store(1, std::memory_order_relaxed);
          }
        }
      }
    }
  });
  return grid;
}

}  // namespace bounce::topology
