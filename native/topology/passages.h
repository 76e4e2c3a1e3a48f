// Light between clusters that no chain of gates joins. Gates are found in the voxel grid, so an opening narrower
// than a voxel (blinds, a grille, a gap under a door) joins nothing and, by the gates alone, lets no light through.
// A renderer that cannot cast a ray per light (Forward Light Cuts' Indirect Shadows on the GPU) weighs such light
// by the share of it that passes, estimated once per topology with the renderer's occlusion test from segments
// between random points of the two clusters' surfaces: a rectangle around where the clear segments cross (a gate
// fitted to the rays) and, per direction bin, the form-factor-weighted fraction of the segments through it that
// are clear (the mean visibility between clusters of hierarchical radiosity, kept per direction because slats and
// fins pass light along some directions only). A solid wall passes none.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "segmentation.h"
#include "skeleton.h"

namespace bounce::topology {

struct Topology;

inline constexpr uint32_t kMaxPassageClusters = 1024;  // the slot table is dense: 4 MiB at most
inline constexpr int kPassageBinsPerSide = 8;          // TOPOLOGY_PASSAGE_BINS_PER_SIDE
inline constexpr int kPassageBins = kPassageBinsPerSide * kPassageBinsPerSide;

// Light between two clusters no chain of gates joins: it crosses `gate`, the rectangle around where the clear
// segments between them cross (clusters: the two, the lower first; normal: their mean direction), and passes with
// the share for its direction's bin (topology_passage_bin of the direction from the lower cluster to the higher)
// in the table of its ends' distances from the rectangle's plane (topology_passage_table): share[table * bins + bin].
struct Passage {
  Gate gate;
  std::array<float, 2 * kPassageBins> share{};
};

struct Passages {
  // Per pair of clusters (a * cluster count + b, both orders): 0 when nothing passes between them or the gates
  // join them, else 1 + the index of their passage. Empty when not estimated.
  std::vector<uint32_t> slot;
  std::vector<Passage> passages;
  std::size_t count() const { return passages.size(); }
};

// The passages between clusters in different components. `clear` says whether the segment between two points
// lifted off their surfaces is unoccluded. Empty when every cluster is in one component, with more than
// kMaxPassageClusters clusters, or without a test. Deterministic (fixed draws).
using SegmentClear = std::function<bool(glm::vec3 from, glm::vec3 to)>;
Passages estimate_passages(const Topology& topology, std::span<const glm::vec3> soup, const SegmentClear& clear,
                           const CancelCheck& cancelled = {});

}  // namespace bounce::topology
