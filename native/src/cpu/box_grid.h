// A grid of equal boxes over a scene's bounds, for what is learned by place (LandingGuide, SkyGuide).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace bounce::cpu {

struct BoxGrid {
  glm::vec3 lo{0.0f}, cell_size{1.0f};
  glm::ivec3 cells{0};  // 0 where the bounds were empty or not finite

  BoxGrid() = default;
  // `cells_per_side` boxes along the longest side; flat sides get one box as thick as a thousandth of the
  // longest side, since a box needs a volume.
  BoxGrid(glm::vec3 lo_bound, glm::vec3 hi_bound, int cells_per_side) {
    const glm::vec3 extent = glm::max(hi_bound - lo_bound, glm::vec3(0.0f));
    const float longest = std::max({extent.x, extent.y, extent.z});
    if (!(longest > 0.0f) || !std::isfinite(longest)) return;
    const glm::vec3 thick = glm::max(extent, glm::vec3(1e-3f * longest));
    cells = glm::clamp(glm::ivec3(glm::ceil(thick / longest * float(cells_per_side))), 1, cells_per_side);
    cell_size = thick / glm::vec3(cells);
    lo = 0.5f * (lo_bound + hi_bound) - 0.5f * thick;
  }
  std::size_t size() const { return std::size_t(cells.x) * std::size_t(cells.y) * std::size_t(cells.z); }
  std::size_t index(glm::ivec3 cell) const {
    return (std::size_t(cell.z) * std::size_t(cells.y) + std::size_t(cell.y)) * std::size_t(cells.x) +
           std::size_t(cell.x);
  }
  glm::ivec3 cell(std::size_t index) const {
    return {int(index % std::size_t(cells.x)), int(index / std::size_t(cells.x) % std::size_t(cells.y)),
            int(index / (std::size_t(cells.x) * std::size_t(cells.y)))};
  }
  // The box holding `point`, or the nearest; size() for a point that is not finite or an empty grid.
  std::size_t index_of(glm::vec3 point) const {
    const glm::vec3 at = (point - lo) / cell_size;
    if (size() == 0 || !std::isfinite(at.x) || !std::isfinite(at.y) || !std::isfinite(at.z)) return size();
    return index(glm::clamp(glm::ivec3(glm::floor(at)), glm::ivec3(0), cells - 1));
  }
};

}  // namespace bounce::cpu
