#include "occluders.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "common/parallel.h"
#include "shared_glsl.h"
#include "surface_samples.h"
#include "topology.h"

namespace bounce::topology {
namespace {

constexpr int kSamplesPerCell = 4;  // surface draws per surface cell, by area, to find the cells and their sides
constexpr std::size_t kMaxSamples = std::size_t(1) << 22;
constexpr int kRaysPerBin = 2;  // stratified across the bin: halves

struct CellSides {
  std::size_t cell;
  glm::vec3 position;  // a surface point in the cell
  glm::vec3 normal;    // its unit normal; the cell's rays leave from it toward its front and from its back
};

}  // namespace

Occluders estimate_occluders(const Topology& topology, std::span<const glm::vec3> soup, const FirstHit& first_hit,
                             const CancelCheck& cancelled) {
  const GridShape& shape = topology.grid.shape;
  if (!first_hit || shape.empty()) return {};
  const auto voxel = float(shape.voxel_size);
  // Surface area over a voxel face's: about the surface cells' count.
  const std::size_t count =
      std::min(kMaxSamples, std::size_t(std::ceil(kSamplesPerCell * surface_area(soup) / (double(voxel) * voxel))) + 1);
  Draws draws{0x0CC1D3ull};
  std::vector<uint32_t> slot(shape.padded_count(), 0u);
  std::vector<CellSides> cells;
  for (const SurfaceSample& sample : sample_surfaces(soup, count, draws)) {
    const glm::ivec3 v = shape.voxel_at(glm::dvec3(sample.position));
    if (!shape.inside(v)) continue;
    const std::size_t cell = shape.index(v);
    if (slot[cell] != 0) continue;
    cells.push_back({cell, sample.position, sample.normal});
    slot[cell] = uint32_t(cells.size());
  }
  Occluders occluders;
  occluders.hits.resize(cells.size() * kPassageBins);
  const float lift = 2e-3f * voxel;  // off the surface, clear of float rounding and far inside a voxel
  std::mutex check_mutex;
  parallel_for(cells.size(), 0, 64, [&](std::size_t i) {
    if (cancelled && i % 4096 == 0) {
      std::lock_guard lock(check_mutex);
      if (cancelled()) throw Cancelled{};
    }
    const CellSides& c = cells[i];
    Draws jitter{0x0CC1D3ull ^ uint64_t(c.cell)};
    for (int bin = 0; bin < kPassageBins; ++bin) {
      std::array<Occluders::Hit, kRaysPerBin> hits;
      std::array<glm::vec3, kRaysPerBin> points;  // where each valid ray met a surface, from the cell's point
      int valid = 0;
      for (int k = 0; k < kRaysPerBin; ++k) {
        const glm::vec3 direction = shared::topology_passage_bin_direction(
            bin, 0.5f * (float(k) + float(jitter.uniform())), float(jitter.uniform()));
        const float facing = glm::dot(direction, c.normal);
        if (facing == 0.0f) continue;
        // From the side the direction leaves: a thin surface's two sides see different rooms. A ray that meets the
        // back of a face started inside a closed object, and tells nothing of what a receiver in the cell on another
        // surface sees: from a surface's back (the floor at a pillar's foot), or from its front within
        // behind_occluder's slack (the floor under a rug, the wall behind a picture, whose own inside hid every light
        // from the receivers on top: the budget's sunlit room had blotches on its rug, the second bounce 0.95 of
        // Cycles, middle third 0.89; 1.03 and 1.02 without such rays).
        Occluders::Hit hit = first_hit(c.position + (facing > 0.0f ? lift : -lift) * c.normal, direction);
        const bool back_face = glm::dot(hit.normal, direction) > 0.0f;
        if (back_face && (facing < 0.0f || hit.distance < 2.0f * voxel)) continue;
        if (back_face) hit.normal = -hit.normal;
        if (std::isfinite(hit.distance)) hit.plane = glm::dot(hit.normal, hit.distance * direction);
        points[valid] = hit.distance * direction;
        hits[valid++] = hit;
      }
      if (valid < kRaysPerBin) continue;  // a bin the cell's surface cannot tell about
      // The nearest surface stands for the bin, for the share of its rays that meet a surface not behind its plane
      // (behind_occluder's slack): a light behind the plane is hidden along those rays only. A ray that meets a
      // surface behind the plane passes what lies between: from a ceiling beside a window, the sill's plane held the
      // whole floor below it, and an empty room's ceiling lost 2.0 % of its floor's light to bins whose other ray met
      // the floor within the distance rule this replaces, 1.25 times the nearest plus two voxels (1.3 % now:
      // TopologyOccluders.AnEmptyRoomsCeilingSeesItsFloor).
      Occluders::Hit& bin_hit = occluders.hits[i * kPassageBins + bin];
      bin_hit = *std::min_element(hits.begin(), hits.end(),
                                  [](const auto& a, const auto& b) { return a.distance < b.distance; });
      int in_front = 0;
      for (std::size_t k = 0; k < kRaysPerBin; ++k)
        if (std::isfinite(hits[k].distance) &&
            !shared::behind_occluder(bin_hit.normal, bin_hit.plane, points[k], hits[k].distance,
                                     TOPOLOGY_WITHIN_CLUSTER, voxel))
          ++in_front;
      bin_hit.share = float(in_front) / float(kRaysPerBin);
    }
  });
  occluders.slot = std::move(slot);
  return occluders;
}

std::span<const Occluders::Hit> cell_hits(const Occluders& occluders, const GridShape& shape, glm::vec3 x) {
  if (occluders.slot.empty()) return {};
  const glm::ivec3 v = shape.voxel_at(glm::dvec3(x));
  if (!shape.inside(v)) return {};
  const uint32_t slot = occluders.slot[shape.index(v)];
  if (slot == 0) return {};
  return std::span(occluders.hits).subspan(std::size_t(slot - 1) * kPassageBins, kPassageBins);
}

}  // namespace bounce::topology
