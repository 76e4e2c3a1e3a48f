// The curvilinear skeleton of the empty space, as a graph, and the map from every empty voxel to its
// nearest skeleton node through the empty space (Noël and Biri 2014, Sec. IV.A).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "voxel_grid.h"

namespace bounce::topology {

inline constexpr uint32_t kNoNode = std::numeric_limits<uint32_t>::max();

// An undirected graph in compressed rows: the neighbours of node n are adjacency[offsets[n] .. offsets[n + 1]).
struct Graph {
  std::vector<uint32_t> offsets{0};
  std::vector<uint32_t> adjacency;

  size_t node_count() const { return offsets.size() - 1; }
  size_t edge_count() const { return adjacency.size() / 2; }
  std::span<const uint32_t> neighbours(uint32_t n) const {
    return {adjacency.data() + offsets[n], adjacency.data() + offsets[n + 1]};
  }
  size_t degree(uint32_t n) const { return offsets[n + 1] - offsets[n]; }
  // From a list of edges (a, b), a != b, each given once.
  static Graph from_edges(size_t nodes, std::span<const std::pair<uint32_t, uint32_t>> edges);
};

struct Skeleton {
  Graph graph;
  std::vector<glm::vec3> position;   // world space, the centre of the node's most central voxel
  std::vector<float> radius;         // world space: radius of the maximal empty ball centred at the node
  std::vector<uint32_t> voxel_node;  // per padded cell: the nearest node through the empty space; kNoNode on solid
  size_t voxels = 0;                 // skeleton voxels before junction voxels were merged into nodes
  size_t pruned_voxels = 0;          // voxels of spurious branches removed
};

// Thrown out of the precomputation when its cancel callback says so.
struct Cancelled {};

// Returns true to cancel; called every few thousand voxels.
using CancelCheck = std::function<bool()>;

// Distance-ordered homotopic thinning (Pudney 1998) of the empty space of `grid`, so the skeleton is centred
// in it: simple points go in order of increasing distance to the solid, and points that become 1-D isthmuses
// stay (Couprie and Bertrand 2014), which keeps the curves into corridors and rooms. Two departures from
// homotopy, both on purpose: a point whose removal only opens a cavity of the empty space (its background
// neighbours belong to different solid components) goes too, so solid objects floating in the empty space
// leave curves, not closed surfaces around them; and side branches shorter than the maximal ball at their
// junction are pruned afterwards. Components and tunnels (b0 and b1) of the empty space are preserved.
// Junction voxels merge into one node; the nearest-node map is a chamfer (3, 4, 5) Dijkstra through the
// empty space from the skeleton voxels.
Skeleton skeletonize(const VoxelGrid& grid, std::span<const uint32_t> squared_distance,
                     const CancelCheck& cancelled = {});

// Betti numbers of a voxel set (closed unit cubes) or of a graph.
struct Betti {
  size_t components = 0;  // b0
  size_t tunnels = 0;     // b1: independent cycles
  size_t cavities = 0;    // b2
};
// The empty space of `grid`, from its Euler characteristic and its and the solid's components.
Betti empty_space_betti(const VoxelGrid& grid);
Betti graph_betti(const Graph& graph);
// Connected components of a graph: a label per node, labels 0..count-1 by first node.
std::vector<uint32_t> graph_components(const Graph& graph, size_t* count = nullptr);

}  // namespace bounce::topology
