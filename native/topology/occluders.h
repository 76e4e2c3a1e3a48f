// Occluders inside a cluster. The topology method counts every light of a receiver's own cluster without a test
// (a visibility cluster is a region of the empty space whose points mostly see each other, Noel and Biri 2014,
// Sec. IV.B), so blocks in a room and the piers of a gallery cast no indirect shadow: the Cornell box's first
// bounce was 1.08 of Cycles' with the Topology method and FLC's Indirect Shadows alike. Both look up instead of a
// ray per light and receiver (FLC on the GPU has none; the Topology method keeps its rays for clusters the gates do
// not join), per surface voxel and direction bin (topology_passage_bin), the surface
// rays from the voxel's surface along the bin meet first, found once per topology with the ray tracer: a light
// behind that surface's plane is hidden, from the share of the bin's rays that meet it (a pier covering half a
// bin hides half of what is behind it). The plane, not the distance, decides, because the distance to a concave
// room's walls changes across a bin; the plane of the wall the rays meet holds the lights on that wall. A light
// from another cluster is hidden the same way where the segment enters the receiver's cluster through a gate behind
// that plane too: a gate bounds where light enters a cluster, not what stands inside it (with the occluders inside
// clusters only, the Topology method kept 1.07 of its shadow rays' light in an open box with blocks, 1.01 now).
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "passages.h"
#include "shared_glsl.h"

namespace bounce::topology {

struct Topology;

struct Occluders {
  // Per padded grid cell: 0, or 1 + the cell's slot (cells that hold surface).
  std::vector<uint32_t> slot;
  // Per slot and bin, of two rays stratified across the bin, the surface the nearer meets and the share that meet
  // a surface not behind its plane: a light behind that plane is hidden from that share of the bin.
  struct Hit {
    float distance = std::numeric_limits<float>::infinity();  // infinity: no surface
    glm::vec3 normal{0.0f};                                   // unit, facing the ray's origin
    float share = 0.0f;  // of the bin's rays that meet it or a surface in front of its plane
    float plane = 0.0f;  // dot(normal, its point - the cell's surface point): the plane, seen from the cell
  };
  std::vector<Hit> hits;
};

struct GridShape;

// The hits of the cell holding a receiver at x, one per direction bin; empty where the cell holds no surface or x
// lies outside the grid. Looked up once per receiver, for all its lights.
std::span<const Occluders::Hit> cell_hits(const Occluders& occluders, const GridShape& shape, glm::vec3 x);
// The share of a light at `offset` from a receiver (the light's position less the receiver's) that the surfaces of
// the receiver's cell (cell_hits) leave to it: 1 unless the surface that stands for the offset's bin has the light
// behind its plane (behind_occluder), then 1 - its share. The GPU's topology_unoccluded
// (shaders/topology_visibility/visibility.glsl) with the hit unpacked.
// reach: how far from the receiver the segment enters its cluster through a gate (behind_occluder);
// TOPOLOGY_WITHIN_CLUSTER for a light inside it.
// Inline: the Topology method calls it per light and receiver, the most frequent test of its gathering.
inline float unoccluded(std::span<const Occluders::Hit> hits, glm::vec3 offset, float reach, float voxel) {
  const float distance2 = glm::dot(offset, offset);
  if (hits.empty() || !(distance2 > 0.0f)) return 1.0f;
  // The octahedral map needs no unit direction: it divides by the L1 norm.
  const Occluders::Hit& hit = hits[std::size_t(shared::topology_passage_bin(offset))];
  if (!std::isfinite(hit.distance) ||
      !shared::behind_occluder(hit.normal, hit.plane, offset, std::sqrt(distance2), reach, voxel))
    return 1.0f;
  return 1.0f - hit.share;
}

// The first surface along a ray: its distance (infinity when none) and unit geometric normal (the counter-clockwise
// front's, whichever side the ray meets).
using FirstHit = std::function<Occluders::Hit(glm::vec3 origin, glm::vec3 direction)>;
// Empty without a ray tracer. Deterministic (fixed draws).
Occluders estimate_occluders(const Topology& topology, std::span<const glm::vec3> soup, const FirstHit& first_hit,
                             const CancelCheck& cancelled = {});

}  // namespace bounce::topology
