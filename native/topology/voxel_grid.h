// A dense voxel grid over the scene's bounds, padded by one voxel on every side.
//
// The padding holds the outside of the grid, which counts as solid: the empty space is bounded, and loops
// over a voxel's 26 neighbours never need a bounds check. Voxel (x, y, z) of the unpadded grid, x in
// [0, dims.x), is cell (x + 1, y + 1, z + 1) of the padded arrays.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace bounce::topology {

struct GridShape {
  glm::ivec3 dims{0};       // voxels per axis, without the padding
  glm::dvec3 origin{0.0};   // world position of the corner of voxel (0, 0, 0)
  double voxel_size = 1.0;  // world units per voxel edge

  glm::ivec3 padded() const { return dims + 2; }
  size_t padded_count() const {
    const glm::ivec3 p = padded();
    return size_t(p.x) * size_t(p.y) * size_t(p.z);
  }
  size_t voxel_count() const { return size_t(dims.x) * size_t(dims.y) * size_t(dims.z); }
  bool empty() const { return dims.x <= 0 || dims.y <= 0 || dims.z <= 0; }

  // Padded index of unpadded voxel v.
  size_t index(glm::ivec3 v) const {
    const glm::ivec3 p = padded();
    return (size_t(v.z + 1) * size_t(p.y) + size_t(v.y + 1)) * size_t(p.x) + size_t(v.x + 1);
  }
  glm::ivec3 voxel_of_index(size_t i) const {
    const glm::ivec3 p = padded();
    const int x = int(i % size_t(p.x)), y = int((i / size_t(p.x)) % size_t(p.y)), z = int(i / (size_t(p.x) * p.y));
    return {x - 1, y - 1, z - 1};
  }
  bool inside(glm::ivec3 v) const {
    return v.x >= 0 && v.y >= 0 && v.z >= 0 && v.x < dims.x && v.y < dims.y && v.z < dims.z;
  }
  glm::dvec3 centre(glm::ivec3 v) const { return origin + (glm::dvec3(v) + 0.5) * voxel_size; }
  // The voxel containing world point p (may be outside the grid).
  glm::ivec3 voxel_at(glm::dvec3 p) const;

  // Offsets of the 26 neighbours in the padded arrays, in the order of neighbour_offsets().
  std::array<std::ptrdiff_t, 26> neighbour_strides() const;
};

// The 26 neighbour offsets: all of {-1, 0, 1}^3 but the centre, z slowest.
const std::array<glm::ivec3, 26>& neighbour_offsets();

// A binary grid: solid[i] != 0 where geometry touches voxel i (padded index); the padding is solid.
struct VoxelGrid {
  GridShape shape;
  std::vector<uint8_t> solid;

  size_t empty_count() const;
};

}  // namespace bounce::topology
