#include "passages.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec2.hpp>

#include "common/parallel.h"
#include "shared_glsl.h"
#include "surface_samples.h"
#include "topology.h"

namespace bounce::topology {
namespace {

static_assert(kPassageBinsPerSide == TOPOLOGY_PASSAGE_BINS_PER_SIDE);
constexpr int kSurfaceSamples = 1 << 16;  // points drawn on the surfaces, by area; each counts on both sides
constexpr int kProbeDraws = 128;          // point pairs that find whether anything passes between two clusters
constexpr int kDraws = 4096;              // point pairs of a pair of clusters that pass light, over the bins

struct SurfacePoint {
  glm::vec3 position, normal;  // normal: toward the side whose cluster holds the point
};

// Points on the surfaces by area, each with the cluster of either side (Topology::cluster_at, Side::Front).
// Each point lifted off its surface by `lift`.
std::vector<std::vector<SurfacePoint>> points_by_cluster(const Topology& topology, std::span<const glm::vec3> soup,
                                                         const SegmentClear& clear, float lift) {
  std::vector<std::vector<SurfacePoint>> by_cluster(topology.cluster_count);
  Draws draws{0x5EEDull};
  for (const SurfaceSample& sample : sample_surfaces(soup, kSurfaceSamples, draws)) {
    const glm::vec3 p = sample.position, unit = sample.normal;
    for (const glm::vec3& normal : {unit, -unit}) {
      // The lookup must reach its voxel without crossing a surface: within a voxel of a thin wall, the nearest
      // empty voxel may lie behind it, and a point there would pass as the other room's.
      const glm::vec3 lifted = p + lift * normal;
      const uint32_t cluster = topology.cluster_at(lifted, normal, Topology::Side::Front, clear);
      if (cluster < topology.cluster_count) by_cluster[cluster].push_back({lifted, normal});
    }
  }
  return by_cluster;
}

struct Segment {
  glm::vec3 from, to;  // from the lower cluster's surface to the higher's, lifted off them
  double weight;       // the form factor's kernel
  bool clear;
};

// Where a clear segment from cluster a to cluster b crosses what divides them (a clear segment also grazes the
// solid voxels of furniture between clusters the gates join, so only a change of component counts): the middle of
// the first stretch of solid voxels with empty voxels of different components on its two sides; else where it
// leaves the solid voxels it starts in, or enters those it ends in, when the empty voxels beyond are not of its
// end's component (an end on a slat, inside the closed gaps); else the segment's middle.
glm::vec3 crossing(const Topology& topology, uint32_t a, uint32_t b, const Segment& segment) {
  const GridShape& shape = topology.grid.shape;
  const float length = glm::distance(segment.from, segment.to);
  const int steps = std::clamp(int(4.0f * length / float(shape.voxel_size)), 2, 8192);
  const auto at = [&](int step) { return glm::mix(segment.from, segment.to, float(step) / float(steps)); };
  uint32_t first = kNoNode, last = kNoNode;  // the components of the first and the last empty voxel in a cluster
  int first_empty = -1, run = -1;            // run: the first step of the current stretch of solid voxels
  for (int step = 0; step <= steps; ++step) {
    const glm::ivec3 v = shape.voxel_at(glm::dvec3(at(step)));
    if (!shape.inside(v)) continue;
    const std::size_t index = shape.index(v);
    if (topology.grid.solid[index] != 0) {
      if (run < 0) run = step;
      continue;
    }
    const uint32_t cluster = topology.cluster_of_node(topology.skeleton.voxel_node[index]);
    if (cluster == kNoNode) continue;
    const uint32_t component = topology.component[cluster];
    if (run >= 0 && last != kNoNode && component != last) return at((run + step) / 2);
    if (first == kNoNode) first = component, first_empty = step;
    run = -1;
    last = component;
  }
  if (first != kNoNode && first != topology.component[a]) return at(first_empty);
  if (last != kNoNode && run >= 0 && last != topology.component[b]) return at(run);
  return 0.5f * (segment.from + segment.to);
}

// The unit normal of the plane that best fits the weighted points around `centre` (their covariance's smallest
// eigenvector, by power iteration on trace - covariance), facing as `toward`; `toward` itself when the points lie
// on no plane (the smallest eigenvalue not well below the middle one).
glm::vec3 plane_normal(const std::vector<std::pair<glm::dvec3, double>>& points, glm::dvec3 centre, glm::dvec3 toward) {
  glm::dmat3 covariance(0.0);
  for (const auto& [p, w] : points) {
    const glm::dvec3 d = p - centre;
    covariance += w * glm::outerProduct(d, d);
  }
  const double trace = covariance[0][0] + covariance[1][1] + covariance[2][2];
  if (!(trace > 0.0)) return glm::vec3(toward);
  const auto dominant = [](const glm::dmat3& m, glm::dvec3 v) {
    for (int i = 0; i < 64; ++i) {
      const glm::dvec3 next = m * v;
      const double length = glm::length(next);
      if (!(length > 0.0)) break;
      v = next / length;
    }
    return v;
  };
  const glm::dvec3 smallest = dominant(glm::dmat3(trace) - covariance, toward);
  const glm::dvec3 largest =
      dominant(covariance, glm::dvec3(toward.y - toward.z, toward.z - toward.x, toward.x - toward.y) + 0.1);
  const double low = glm::dot(smallest, covariance * smallest), high = glm::dot(largest, covariance * largest);
  const double middle = trace - low - high;
  if (!(low < 0.25 * middle)) return glm::vec3(toward);
  return glm::vec3(glm::dot(smallest, toward) < 0.0 ? -smallest : smallest);
}

// The rectangle through which the clear segments cross, in the plane that fits their crossings (or facing their
// mean direction), and the share of the light crossing it that passes, per direction bin.
std::optional<Passage> fit_passage(uint32_t a, uint32_t b, const std::vector<Segment>& segments,
                                   const Topology& topology) {
  glm::dvec3 direction(0.0), centre(0.0);
  double clear_weight = 0.0;
  std::vector<std::pair<glm::dvec3, double>> crossings;
  for (const Segment& s : segments)
    if (s.clear) {
      direction += s.weight * glm::dvec3(glm::normalize(s.to - s.from));
      crossings.emplace_back(crossing(topology, a, b, s), s.weight);
      centre += s.weight * crossings.back().first;
      clear_weight += s.weight;
    }
  if (!(clear_weight > 0.0) || !(glm::length(direction) > 0.0)) return std::nullopt;
  Passage passage;
  passage.gate.clusters = {a, b};
  passage.gate.centre = glm::vec3(centre / clear_weight);
  passage.gate.normal = plane_normal(crossings, centre / clear_weight, glm::normalize(direction));
  // The crossings of the clear segments with the rectangle's plane, in a basis of it, and the smallest rectangle
  // around them (over its orientation, in steps of a degree), half a voxel wider on every side. Around the
  // crossings' weighted mean and along their principal axes it reached past the opening: light crosses an opening
  // unevenly (a low sun through a window's lower half), so the mean lies off the opening's centre and the axes
  // turn off its edges. Then the wall around the opening passed light, and its blocked segments, heavy by their
  // form factor at the wall, lowered the share through the opening itself: the budget's sunlit interior had
  // 2.66 x 1.88 m for a 2 x 1.3 m window.
  const glm::vec3 n = passage.gate.normal;
  const glm::vec3 t1 =
      glm::normalize(std::abs(n.x) < 0.9f ? glm::cross(n, glm::vec3(1, 0, 0)) : glm::cross(n, glm::vec3(0, 1, 0)));
  const glm::vec3 t2 = glm::cross(n, t1);
  std::vector<glm::vec2> on_plane;
  for (const Segment& s : segments) {
    if (!s.clear) continue;
    const float from_side = glm::dot(s.from - passage.gate.centre, n),
                to_side = glm::dot(s.to - passage.gate.centre, n);
    if (!(from_side * to_side < 0.0f)) continue;
    const glm::vec3 at = s.from + (s.to - s.from) * (from_side / (from_side - to_side)) - passage.gate.centre;
    on_plane.emplace_back(glm::dot(at, t1), glm::dot(at, t2));
  }
  if (on_plane.empty()) return std::nullopt;
  const auto extent = [&on_plane](glm::vec2 axis) {
    glm::vec2 low(std::numeric_limits<float>::max()), high(std::numeric_limits<float>::lowest());
    for (const glm::vec2& uv : on_plane) {
      const glm::vec2 along(glm::dot(uv, axis), axis.x * uv.y - axis.y * uv.x);
      low = glm::min(low, along);
      high = glm::max(high, along);
    }
    return std::pair{low, high};
  };
  glm::vec2 axis(1.0f, 0.0f);
  float smallest = std::numeric_limits<float>::max();
  for (int degree = 0; degree < 90; ++degree) {
    const float angle = glm::radians(float(degree));
    const glm::vec2 candidate(std::cos(angle), std::sin(angle));
    const auto [low, high] = extent(candidate);
    const float area = (high.x - low.x) * (high.y - low.y);
    if (area < smallest) smallest = area, axis = candidate;
  }
  const auto [low, high] = extent(axis);
  passage.gate.axis_u = axis.x * t1 + axis.y * t2;
  const glm::vec2 middle = 0.5f * (low + high);
  passage.gate.centre += middle.x * passage.gate.axis_u + middle.y * glm::cross(n, passage.gate.axis_u);
  const float margin = 0.5f * float(topology.grid.shape.voxel_size);
  passage.gate.half_u = 0.5f * (high.x - low.x) + margin;
  passage.gate.half_v = 0.5f * (high.y - low.y) + margin;
  passage.gate.radius = std::hypot(passage.gate.half_u, passage.gate.half_v);
  // Per table and bin, and over every direction for the bins no segment crossing the rectangle fell in; a table no
  // segment fell in takes the other's shares. Segments from the slats of blinds see the room through their gaps
  // more freely than those from a lawn beyond: one table for both let a sunlit lawn light a room 2.5 times as much
  // as Cycles.
  std::array<std::array<double, kPassageBins + 1>, 2> weight{}, passed{};
  const Gate& g = passage.gate;
  const auto voxel = float(topology.grid.shape.voxel_size);
  for (const Segment& s : segments) {
    if (!shared::in_gate_cone(s.from, g.centre, g.normal, g.axis_u, g.half_u, g.half_v, s.to)) continue;
    const int table = shared::topology_passage_table(glm::dot(s.from - g.centre, g.normal),
                                                     glm::dot(s.to - g.centre, g.normal), voxel);
    for (const int bin : {shared::topology_passage_bin(glm::normalize(s.to - s.from)), kPassageBins}) {
      weight[table][bin] += s.weight;
      if (s.clear) passed[table][bin] += s.weight;
    }
  }
  if (!(passed[0][kPassageBins] + passed[1][kPassageBins] > 0.0)) return std::nullopt;
  for (int table = 0; table < 2; ++table) {
    const int from = weight[table][kPassageBins] > 0.0 ? table : 1 - table;
    for (int bin = 0; bin < kPassageBins; ++bin)
      passage.share[std::size_t(table * kPassageBins + bin)] =
          float(weight[from][bin] > 0.0 ? passed[from][bin] / weight[from][bin]
                                        : passed[from][kPassageBins] / weight[from][kPassageBins]);
  }
  return passage;
}

}  // namespace

Passages estimate_passages(const Topology& topology, std::span<const glm::vec3> soup, const SegmentClear& clear,
                           const CancelCheck& cancelled) {
  const uint32_t count = topology.cluster_count;
  if (!clear || count > kMaxPassageClusters || topology.component.size() != count ||
      std::all_of(topology.component.begin(), topology.component.end(), [](uint32_t c) { return c == 0; }))
    return {};
  const auto voxel = float(topology.grid.shape.voxel_size);
  const float lift = 2e-3f * voxel;  // off the surface, clear of float rounding and far inside a voxel
  const std::vector<std::vector<SurfacePoint>> points = points_by_cluster(topology, soup, clear, lift);
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  for (uint32_t a = 0; a < count; ++a)
    for (uint32_t b = a + 1; b < count; ++b)
      if (topology.component[a] != topology.component[b] && !points[a].empty() && !points[b].empty())
        pairs.emplace_back(a, b);
  std::vector<std::optional<Passage>> found(pairs.size());
  // The check reports progress through the caller's state: one thread at a time.
  std::mutex check_mutex;
  parallel_for(pairs.size(), 0, 1, [&](std::size_t i) {
    if (cancelled && i % 64 == 0) {
      std::lock_guard lock(check_mutex);
      if (cancelled()) throw Cancelled{};
    }
    const auto [a, b] = pairs[i];
    Draws draws{0xC1EA2ull ^ (uint64_t(a) << 32 | b)};
    std::vector<Segment> segments;
    bool any_passed = false;
    for (int k = 0; k < kDraws; ++k) {
      if (k == kProbeDraws && !any_passed) return;  // a wall: nothing passed
      const SurfacePoint& p = points[a][draws.below(points[a].size())];
      const SurfacePoint& q = points[b][draws.below(points[b].size())];
      const glm::vec3 offset = q.position - p.position;
      const float distance2 = glm::dot(offset, offset);
      if (!(distance2 > 0.0f)) continue;
      const glm::vec3 direction = offset / std::sqrt(distance2);
      // The point-to-point form factor's kernel, its distance held to a voxel as the renderers clamp theirs.
      const double w =
          double(std::max(0.0f, glm::dot(p.normal, direction)) * std::max(0.0f, -glm::dot(q.normal, direction))) /
          double(std::max(distance2, voxel * voxel));
      if (!(w > 0.0)) continue;
      const bool passed = clear(p.position, q.position);
      any_passed = any_passed || passed;
      segments.push_back({p.position, q.position, w, passed});
    }
    found[i] = fit_passage(a, b, segments, topology);
  });
  Passages passages;
  passages.slot.assign(std::size_t(count) * count, 0u);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (!found[i]) continue;
    const auto [a, b] = pairs[i];
    passages.passages.push_back(*found[i]);
    passages.slot[std::size_t(a) * count + b] = passages.slot[std::size_t(b) * count + a] =
        uint32_t(passages.passages.size());
  }
  if (passages.passages.empty()) passages.slot.clear();
  return passages;
}

}  // namespace bounce::topology
