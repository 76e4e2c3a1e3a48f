// Exact Euclidean distance transform of the empty space.
#pragma once

#include <cstdint>
#include <vector>

#include "voxel_grid.h"

namespace bounce::topology {

// For every padded cell, the squared Euclidean distance, in voxels, from its centre to the centre of the
// nearest solid cell (the padding included, so the outside of the grid bounds it); 0 on solid cells. Exact:
// three separable passes of the lower envelope of parabolas (Felzenszwalb and Huttenlocher 2012), in
// integers where it matters. The maximal ball at an empty voxel has radius sqrt(d²) - 1/2 voxels.
std::vector<uint32_t> squared_distance_transform(const VoxelGrid& grid);

}  // namespace bounce::topology
