// Conservative binary voxelization of a triangle soup.
#pragma once

#include <span>

#include <glm/vec3.hpp>

#include "voxel_grid.h"

namespace bounce::topology {

// The grid over the bounds of the finite vertices of `soup`: `resolution` voxels along the longest axis, of
// which `margin` empty voxels on each side (fewer when the resolution is too small to hold them), cubic voxels.
// An empty soup or one with no finite triangle gives an empty shape.
GridShape fit_grid(std::span<const glm::vec3> soup, int resolution, int margin);

// Marks solid every voxel a triangle touches, closed boxes against closed triangles (separating-axis test,
// Akenine-Möller 2001), so walls are never missed however thin, and diagonal walls leave no 26-connected
// gap for the empty space to leak through. Triangles with a non-finite vertex are skipped; degenerate ones
// mark the voxels their segment or point touches. Vertices 3i, 3i + 1, 3i + 2 make triangle i.
VoxelGrid voxelize(std::span<const glm::vec3> soup, const GridShape& shape);

}  // namespace bounce::topology
