#include "voxel_grid.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>

namespace bounce::topology {

glm::ivec3 GridShape::voxel_at(glm::dvec3 p) const {
  const glm::dvec3 g = glm::floor((p - origin) / voxel_size);
  const glm::dvec3 limit(1 << 30);
  return glm::ivec3(glm::clamp(g, -limit, limit));
}

std::array<std::ptrdiff_t, 26> GridShape::neighbour_strides() const {
  const glm::ivec3 p = padded();
  std::array<std::ptrdiff_t, 26> strides{};
  const auto& offsets = neighbour_offsets();
  for (size_t i = 0; i < offsets.size(); ++i) {
    strides[i] = (std::ptrdiff_t(offsets[i].z) * p.y + offsets[i].y) * p.x + offsets[i].x;
  }
  return strides;
}

const std::array<glm::ivec3, 26>& neighbour_offsets() {
  static const std::array<glm::ivec3, 26> offsets = [] {
    std::array<glm::ivec3, 26> o{};
    size_t n = 0;
    for (int z = -1; z <= 1; ++z)
      for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x)
          if (x || y || z) o[n++] = {x, y, z};
    return o;
  }();
  return offsets;
}

size_t VoxelGrid::empty_count() const { return size_t(std::count(solid.begin(), solid.end(), uint8_t(0))); }

}  // namespace bounce::topology
