#include "gate_surfaces.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "common/parallel.h"

namespace bounce::topology {
namespace {

constexpr double kProbeDepth = 2.0;      // voxels either side of the plane a probe looks for surfaces
constexpr double kProbesPerVoxel = 4.0;  // across the rectangle, where kMaxProbesPerSide allows
constexpr int kMaxProbesPerSide = 48;
constexpr double kNarrowestGate = 1.0;  // voxels: a gate whose half width is less is left out
constexpr double kWallSpread = 0.5;  // voxels: the blocked probes' middles agree within this (interquartile) on a wall

// The gate fitted to the surfaces around it, or unchanged.
Gate fitted(const Gate& gate, double voxel, const FirstHit& first_hit) {
  const glm::dvec3 n(gate.normal), u(gate.axis_u), v = glm::cross(n, u), centre(gate.centre);
  const double region_u = gate.half_u + 0.5 * voxel, region_v = gate.half_v + 0.5 * voxel;
  const double depth = kProbeDepth * voxel;
  const auto probes = [&](double half) {
    return std::clamp(int(std::ceil(2.0 * half * kProbesPerVoxel / voxel)), 1, kMaxProbesPerSide);
  };
  const int count_u = probes(region_u), count_v = probes(region_v);
  const double step_u = 2.0 * region_u / count_u, step_v = 2.0 * region_v / count_v;
  // Per probe: whether it is clear; where not, the middle of the surfaces it meets, which span
  // [ahead - depth, depth - behind] along the normal from the plane.
  std::vector<uint8_t> clear(std::size_t(count_u) * count_v, 0);
  std::vector<double> wall_middles;
  const auto position = [&](int i, int j) {
    return glm::dvec2(-region_u + (i + 0.5) * step_u, -region_v + (j + 0.5) * step_v);
  };
  int seed = -1;
  double seed_distance = HUGE_VAL;
  for (int j = 0; j < count_v; ++j)
    for (int i = 0; i < count_u; ++i) {
      const glm::dvec2 st = position(i, j);
      const glm::dvec3 on_plane = centre + st.x * u + st.y * v;
      const float ahead = first_hit(glm::vec3(on_plane - depth * n), glm::vec3(n)).distance;
      if (!(ahead < 2.0 * depth)) {
        clear[std::size_t(j) * count_u + i] = 1;
        if (glm::length(st) < seed_distance) seed = j * count_u + i, seed_distance = glm::length(st);
        continue;
      }
      const float behind = first_hit(glm::vec3(on_plane + depth * n), glm::vec3(-n)).distance;
      if (behind < 2.0 * depth) wall_middles.push_back(0.5 * (double(ahead) - double(behind)));
    }
  if (seed < 0) return gate;
  // The clear probes joined to the one nearest the centre: the opening, not the next gap of a blind beside it.
  double lo_u = HUGE_VAL, hi_u = -HUGE_VAL, lo_v = HUGE_VAL, hi_v = -HUGE_VAL;
  std::vector<int> open{seed};
  clear[std::size_t(seed)] = 2;
  while (!open.empty()) {
    const int at = open.back(), i = at % count_u, j = at / count_u;
    open.pop_back();
    const glm::dvec2 st = position(i, j);
    lo_u = std::min(lo_u, st.x - 0.5 * step_u), hi_u = std::max(hi_u, st.x + 0.5 * step_u);
    lo_v = std::min(lo_v, st.y - 0.5 * step_v), hi_v = std::max(hi_v, st.y + 0.5 * step_v);
    for (const auto& [di, dj] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
      const int ni = i + di, nj = j + dj;
      if (ni < 0 || nj < 0 || ni >= count_u || nj >= count_v) continue;
      uint8_t& next = clear[std::size_t(nj) * count_u + ni];
      if (next == 1) next = 2, open.push_back(nj * count_u + ni);
    }
  }
  Gate g = gate;
  glm::dvec3 moved = centre + 0.5 * (lo_u + hi_u) * u + 0.5 * (lo_v + hi_v) * v;
  if (wall_middles.size() >= 4) {
    const auto quantile = [&](double q) {
      const auto at = wall_middles.begin() + std::ptrdiff_t(q * double(wall_middles.size() - 1));
      std::nth_element(wall_middles.begin(), at, wall_middles.end());
      return *at;
    };
    const double lower = quantile(0.25), upper = quantile(0.75), middle = quantile(0.5);
    if (upper - lower <= kWallSpread * voxel) moved += middle * n;
  }
  g.centre = glm::vec3(moved);
  g.half_u = float(0.5 * (hi_u - lo_u));
  g.half_v = float(0.5 * (hi_v - lo_v));
  g.radius = std::hypot(g.half_u, g.half_v);
  return g;
}

}  // namespace

void fit_gates_to_surfaces(const GridShape& shape, const FirstHit& first_hit, std::vector<Gate>& gates,
                           const CancelCheck& cancelled) {
  if (!first_hit || shape.empty()) return;
  std::mutex check_mutex;
  parallel_for(gates.size(), 0, 8, [&](std::size_t i) {
    if (cancelled && i % 256 == 0) {
      std::lock_guard lock(check_mutex);
      if (cancelled()) throw Cancelled{};
    }
    if (!gates[i].needs_ray()) gates[i] = fitted(gates[i], shape.voxel_size, first_hit);
  });
  std::erase_if(gates, [&](const Gate& g) {
    return !g.needs_ray() && std::min(g.half_u, g.half_v) < kNarrowestGate * shape.voxel_size;
  });
}

}  // namespace bounce::topology
