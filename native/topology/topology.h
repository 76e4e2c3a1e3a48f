// The topology of a scene's empty space: voxels, skeleton, visibility clusters and gates (Noël and Biri 2014,
// Sec. IV). A module of its own, on the CPU, knowing nothing of rendering: the topology method's renderer
// uses it, and it is the visibility structure FLC and SSVP can borrow.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "occluders.h"
#include "passages.h"
#include "segmentation.h"
#include "skeleton.h"
#include "voxel_grid.h"

namespace bounce::topology {

struct Settings {
  int resolution = 128;  // voxels along the scene's longest axis (the paper: 256)
  int margin = 2;        // empty voxels around the scene's bounds, inside the resolution
  float alpha = 0.2f;    // similarity of maximal balls within a cluster (Sec. IV.B.2; the paper: 20 %)
};

inline constexpr int kMaxResolution = 256;  // the paper's grid; 256^3 cells take about 1 GB while building

enum class BuildStage { Voxelize, DistanceTransform, Thinning, Segmentation, Clusters, Gates, Count };
const char* build_stage_name(BuildStage stage);

// Called at the start of each stage and during long ones; returns false to cancel (build() then throws
// Cancelled). fraction: of the whole precomputation, roughly by time.
using Progress = std::function<bool(BuildStage stage, float fraction)>;

struct Topology {
  VoxelGrid grid;
  Skeleton skeleton;
  SegmentedSkeleton segmented;
  std::vector<uint32_t> cluster_of;  // per segmented node
  uint32_t cluster_count = 0;
  std::vector<Gate> gates;
  std::vector<uint32_t> component;  // per cluster: its component of the graph the gates make (gate_components)
  // Between clusters in different components: the light that passes through openings narrower than a voxel
  // (estimate_passages; passages.h). Empty when not estimated.
  Passages passages;
  // Inside a cluster: per surface cell and direction bin, the surface that rays meet first (estimate_occluders;
  // occluders.h). Empty when not estimated.
  Occluders occluders;
  bool passages_estimated = false;     // whether they were estimated (they may still be empty)
  bool occluders_estimated = false;    // and the gates fitted to the surfaces (gate_surfaces.h), from the same query
  std::vector<uint32_t> node_cluster;  // per original skeleton node (node_clusters)
  std::array<double, size_t(BuildStage::Count)> stage_ms{};

  // Which side of a surface point a lookup may take.
  enum class Side {
    Either,  // n is any normal of the surface
    Front,   // n points into the side that matters (a view sample's toward the camera, a VPL's lit side)
  };
  // The skeleton node nearest, through the empty space, to a point on a surface with normal n: the first empty
  // voxel from p along n, then (Either) along -n, then the nearest empty neighbour of p's voxel (Front: among
  // those on n's side). kNoNode when p is not finite, outside the grid, or walled in on that side.
  // `reachable`, when given, must accept the segment from p to a voxel's centre for that voxel to count: a
  // renderer with a ray tracer passes its occlusion test, so that a point inside a block thinner than the
  // steps does not reach through it.
  using Reachable = std::function<bool(glm::vec3 from, glm::vec3 to)>;
  uint32_t node_at(glm::vec3 p, glm::vec3 n, Side side = Side::Either, const Reachable& reachable = {}) const;
  // The visibility cluster of that node, kNoNode likewise.
  uint32_t cluster_at(glm::vec3 p, glm::vec3 n, Side side = Side::Either, const Reachable& reachable = {}) const;
  uint32_t cluster_of_node(uint32_t node) const { return node == kNoNode ? kNoNode : node_cluster[node]; }
  // Whether the gates join two clusters (both in the grid).
  bool joined(uint32_t a, uint32_t b) const { return component[a] == component[b]; }
  // Stage times and counts, one line each.
  std::string summary() const;
};

// A ray tracer's answers, for the estimates made from rays: passages (passages.h) from `clear`, occluders
// (occluders.h) and the gates' fit to the surfaces (gate_surfaces.h) from `first_hit`; each estimate is made when
// its query is given.
struct RayQueries {
  SegmentClear clear;
  FirstHit first_hit;
};

// The whole precomputation for the triangle soup (vertices 3i, 3i + 1, 3i + 2), in world space. Settings out of
// range are clamped (resolution to [1, kMaxResolution], alpha to [0, 1]). With a ray tracer's queries, the
// estimates they serve too, in the Gates stage. Throws Cancelled.
Topology build(std::span<const glm::vec3> soup, const Settings& settings, const Progress& progress = {},
               const RayQueries& rays = {});
// `base`, built from the same soup, with the estimates it lacks made from the queries given: what build() with
// them returns, without building the rest again (Forward Light Cuts needs passages and occluders, the Topology
// method occluders only, and a scene rendered with both keeps one topology). Throws Cancelled.
Topology with_ray_estimates(Topology base, std::span<const glm::vec3> soup, const RayQueries& rays,
                            const Progress& progress = {});

// Per padded voxel, its visibility cluster for a renderer that has no rays: its nearest node's, except that a
// cluster's voxels past the plane of a skeleton gate (on the other cluster's side, connected to the opening within
// the gate's circle and two voxels) take the other cluster. Those are the dome of voxels a room's cluster claims
// around a doorway in the next room, whose boundary is a second opening (Gate::needs_ray): a renderer with rays
// confirms light across it with a shadow ray; without one, the light of a floor just past a doorway was lost to
// the room it lies in (Forward Light Cuts' Indirect Shadows, 0.89 of the unshadowed light in a convex room).
std::vector<uint32_t> voxel_clusters_split_at_gates(const Topology& t);

}  // namespace bounce::topology
