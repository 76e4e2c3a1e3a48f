// Gates fitted to the surfaces around their openings. fit_gates_to_boundaries (segmentation.h) places each gate
// from the voxels: its plane on a voxel layer off the wall (a thin wall's layer is a voxel thick), its rectangle
// around the opening's empty voxels plus a voxel, which the conservative voxelization makes up to half a voxel too
// wide or too narrow on each side. A segment crossing a rectangle that stands in front of a wall went through the
// wall, and one crossing the opening missed a rectangle that stopped short of its jambs (a 2 m by 3 m doorway at
// 0.16 m voxels passed 0.92 of the shadow rays' light). With a ray tracer, each rectangle is fitted to the opening
// itself: probes along the gate's normal find where the opening is clear, and the walls they meet around it give
// the plane.
//
// An opening less than two voxels across is left to rays: a gate through it is a rectangle on a gap the
// voxels half close, and the walk through it neither passes the light that crosses the gap outside its voxels nor
// stops the light the gap's sides block. Sunlit room behind blinds at 256^3 (gaps of 8.8 cm, voxels of 5.6 cm),
// the light of the VPLs outside that reached the room through the gaps' gates: 9 % of what shadow rays let
// through, and 1.5 times as much that they block. Without those gates the room and the outside are not joined,
// as at 128^3, where the voxels close the gaps: the renderer casts shadow rays there, FLC's passages
// (passages.h) carry the light.
#pragma once

#include <vector>

#include "occluders.h"
#include "segmentation.h"
#include "voxel_grid.h"

namespace bounce::topology {

// Each gate's rectangle becomes the bounds of the probes along its normal that meet nothing within two voxels
// either side of its plane, over its rectangle widened by half a voxel and joined to the clear probe nearest its
// centre (the opening, not the next gap of a blind); its plane moves to the middle of the surfaces the blocked
// probes meet where they agree (a wall); a gate no probe clears keeps its rectangle. Then every gate less than two
// voxels across is removed. Gates that need a ray anyway (Gate::needs_ray) stay as they are. Deterministic.
void fit_gates_to_surfaces(const GridShape& shape, const FirstHit& first_hit, std::vector<Gate>& gates,
                           const CancelCheck& cancelled = {});

}  // namespace bounce::topology
