// The segmented skeleton, the visibility clusters and the visibility gates (Noël and Biri 2014, Sec. IV.B-C).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "skeleton.h"

namespace bounce::topology {

enum class NodeKind : uint8_t {
  Removed,    // not in the segmented skeleton
  Topology,   // degree other than 2, or kept so that a cycle keeps its nodes
  Curvature,  // curv(n) > 1 (Sec. IV.B.1)
  Coverage,   // outside both maximal balls at its line's ends (Sec. IV.B.1)
  Neck,       // a maximal ball smaller than (1 - alpha) times both of its line's ends' (addition, see segment())
};

struct SegmentedSkeleton {
  std::vector<NodeKind> kind;          // per original node
  std::vector<uint32_t> original;      // per segmented node: its original node
  std::vector<uint32_t> segmented_of;  // per original node: the nearest kept end of its line
  Graph graph;                         // over segmented nodes
  // Each segmented edge once, with the original nodes along the skeleton from its first end to its second.
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  std::vector<std::vector<uint32_t>> edge_paths;
};

// Sec. IV.B.1: topology nodes; lines between them; curvature nodes, recursively; then coverage nodes,
// recursively. A cycle with no node of degree other than 2 gets its widest node as a topology node; a line
// that would become a second edge between the same two nodes, or a loop, keeps inner nodes so the segmented
// graph has the skeleton's cycles. Addition: last, necks, recursively: the inner node of smallest maximal
// ball when that is below (1 - alpha) times both ends' balls. The paper removes nodes so that "important
// variations in the radius of maximal balls" are not lost, but its two tests keep none across a doorway in a
// thin wall when the balls of both rooms reach through it; clustering needs the neck to cut the rooms apart.
SegmentedSkeleton segment(const Skeleton& skeleton, float alpha);

// Sec. IV.B.2: greedy, by decreasing maximal ball. A cluster takes the neighbours of its nodes that are not
// curvature nodes and whose radius is within alpha of the cluster's largest, and the nodes inside a member's
// maximal ball reachable from it. Departure: a node taken for being inside a ball grows the cluster further
// only if it passes the neighbour test too; otherwise a doorway node inside a room's ball would carry the
// room's cluster into the next room. Addition: a cluster with no local maximum of the maximal ball (a passage,
// such as the approach to a doorway) is dissolved into the clusters its nodes reach by steepest ascent of the
// radius. Returns a cluster per segmented node, numbered from 0 in order of first node.
std::vector<uint32_t> visibility_clusters(const Skeleton& skeleton, const SegmentedSkeleton& segmented, float alpha,
                                          uint32_t* count = nullptr);

// Sec. IV.C: a gate on each segmented edge whose ends lie in different clusters. Departure: the paper puts a disk
// at the middle of the edge, radius the smaller of the two maximal balls; here it sits at the neck of the edge's
// skeleton path (its node of smallest maximal ball), orthogonal to the path there. When a doorway node ends the
// edge, the middle lies in the next room and the paper's disk covers a wall; the neck is the doorway. Then
// fit_gates_to_boundaries makes it a rectangle covering the whole opening between the clusters (a ball at the
// neck covers a circle inside a 2 x 3 m doorway, or a fraction of a room's section where a room is split in two).
struct Gate {
  glm::vec3 centre{0.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f};  // from clusters[0]'s side to clusters[1]'s
  glm::vec3 axis_u{1.0f, 0.0f, 0.0f};  // in the gate's plane; the other axis is cross(normal, axis_u)
  float half_u = 0.0f, half_v = 0.0f;  // the rectangle's half extents along axis_u and the other axis
  float radius = 0.0f;                 // of the circle around the rectangle
  std::array<uint32_t, 2> clusters{};
  // Where the gate comes from (add_boundary_gates). A second opening between two clusters a skeleton gate already
  // joins may be the dome of voxels one room's cluster claims around a doorway in the next room, whose rectangle
  // stands in front of the wall: a renderer with a ray tracer confirms a crossing through it with a shadow ray,
  // one without leaves it out.
  enum class Kind : uint8_t { kSkeleton, kBoundary, kSecondOpening };
  Kind kind = Kind::kSkeleton;
  bool needs_ray() const { return kind == Kind::kSecondOpening; }
};
std::vector<Gate> visibility_gates(const Skeleton& skeleton, const SegmentedSkeleton& segmented,
                                   const std::vector<uint32_t>& cluster_of);

// The visibility cluster of every original skeleton node, which the voxels' nearest nodes give to points: its
// line's nearest kept end's, except on an edge between two clusters, whose gate is the boundary: the nodes up to
// the neck take the first end's cluster, the rest the second's. With the nearest end instead, the nodes past a
// doorway's neck took the first room's cluster, and so did a slab of the second room along the wall.
std::vector<uint32_t> node_clusters(const Skeleton& skeleton, const SegmentedSkeleton& segmented,
                                    const std::vector<uint32_t>& cluster_of);

// Each gate becomes the rectangle around the opening between its two clusters, so that light from one reaches
// the other through all of it: its plane faces as the boundary between the clusters' voxels does (the sum of the
// faces' normals, each face to the nearest gate of its pair of clusters) and passes through the neck; the
// opening is the empty voxels of that plane connected to the neck within the two clusters (a doorway inside its
// wall, a room's section where a room is split). voxel_cluster: per padded cell, kNoNode on solid cells.
void fit_gates_to_boundaries(const VoxelGrid& grid, const std::vector<uint32_t>& voxel_cluster,
                             std::vector<Gate>& gates);

// A gate for every piece of the boundary between two clusters' voxels that no gate covers: the rectangle around
// the piece's faces, in the plane through their mean that faces as their normals do on the whole. The paper's
// gates sit on the skeleton's edges (Sec. IV.C), but a voxel takes its nearest node's cluster, so a branch of the
// skeleton reaching into a corner claims a slab of the room around it, and light crossing the slab's boundary
// found no gate (an open box lost 13 % of its indirect light). Two clusters may also touch through several
// openings, one of which holds their skeleton edge's gate: Sponza's galleries open on the court through a row of
// arches, and the Topology method lost half the light that crosses from one cluster to another there. A piece of a
// pair that a fitted gate already joins may also be the dome of voxels one room's cluster claims around a doorway
// in the next room, whose rectangle stands in front of the wall (Gate::Kind).
void add_boundary_gates(const GridShape& shape, const std::vector<uint32_t>& voxel_cluster, std::vector<Gate>& gates);

}  // namespace bounce::topology
