#include "topology.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>

#include <glm/geometric.hpp>

#include "distance_transform.h"
#include "gate_surfaces.h"
#include "voxelize.h"

namespace bounce::topology {

namespace {

// Per cluster: the smallest cluster of its component of the graph the gates make. Second openings
// (Gate::needs_ray) lie beside a skeleton gate of their pair (add_boundary_gates) and join nothing it does not.
std::vector<uint32_t> gate_components(uint32_t cluster_count, std::span<const Gate> gates) {
  std::vector<uint32_t> component(cluster_count);
  std::iota(component.begin(), component.end(), 0u);
  const auto root = [&](uint32_t c) {
    while (component[c] != c) c = component[c] = component[component[c]];
    return c;
  };
  for (const Gate& gate : gates)
    if (!gate.needs_ray() && gate.clusters[0] < cluster_count && gate.clusters[1] < cluster_count) {
      const uint32_t a = root(gate.clusters[0]), b = root(gate.clusters[1]);
      component[std::max(a, b)] = std::min(a, b);
    }
  for (uint32_t c = 0; c < cluster_count; ++c) component[c] = root(c);
  return component;
}

}  // namespace

const char* build_stage_name(BuildStage stage) {
  switch (stage) {
    case BuildStage::Voxelize:
      return "voxelize";
    case BuildStage::DistanceTransform:
      return "distance transform";
    case BuildStage::Thinning:
      return "thinning";
    case BuildStage::Segmentation:
      return "segmentation";
    case BuildStage::Clusters:
      return "visibility clusters";
    case BuildStage::Gates:
      return "visibility gates";
    case BuildStage::Count:
      break;
  }
  return "?";
}

uint32_t Topology::node_at(glm::vec3 p, glm::vec3 n, Side side, const Reachable& reachable) const {
  const GridShape& shape = grid.shape;
  if (shape.empty() || !std::isfinite(p.x + p.y + p.z)) return kNoNode;
  if (!std::isfinite(n.x + n.y + n.z)) n = glm::vec3(0.0f);
  const auto node_in = [&](glm::ivec3 v) {
    if (!shape.inside(v)) return kNoNode;
    const uint32_t node = skeleton.voxel_node[shape.index(v)];
    return node == kNoNode || !reachable || reachable(p, glm::vec3(shape.centre(v))) ? node : kNoNode;
  };
  const bool front = side == Side::Front && glm::dot(n, n) > 0.0f;
  for (double sign : {1.0, -1.0}) {
    if (front && sign < 0.0) break;
    for (double step = 0.5; step <= 2.0 && glm::dot(n, n) > 0.0f; step += 0.5) {
      const uint32_t node = node_in(shape.voxel_at(glm::dvec3(p) + sign * step * shape.voxel_size * glm::dvec3(n)));
      if (node != kNoNode) return node;
    }
  }
  const glm::ivec3 v = shape.voxel_at(glm::dvec3(p));
  uint32_t nearest = node_in(v);
  double best = 1e300;
  if (nearest != kNoNode) return nearest;
  for (const glm::ivec3& o : neighbour_offsets()) {
    if (front && glm::dot(glm::vec3(o), n) <= 0.0f) continue;
    const uint32_t node = node_in(v + o);
    const double d = glm::distance(shape.centre(v + o), glm::dvec3(p));
    if (node != kNoNode && d < best) nearest = node, best = d;
  }
  return nearest;
}

uint32_t Topology::cluster_at(glm::vec3 p, glm::vec3 n, Side side, const Reachable& reachable) const {
  return cluster_of_node(node_at(p, n, side, reachable));
}

std::string Topology::summary() const {
  std::string s;
  char line[160];
  std::snprintf(line, sizeof line, "grid %dx%dx%d (%.4g per voxel), %zu empty voxels\n", grid.shape.dims.x,
                grid.shape.dims.y, grid.shape.dims.z, grid.shape.voxel_size, grid.empty_count());
  s += line;
  std::snprintf(line, sizeof line,
                "skeleton %zu voxels (%zu pruned), %zu nodes, %zu edges; segmented %zu nodes; %u clusters, %zu gates, "
                "%zu passages\n",
                skeleton.voxels, skeleton.pruned_voxels, skeleton.graph.node_count(), skeleton.graph.edge_count(),
                segmented.original.size(), cluster_count, gates.size(), passages.count());
  s += line;
  for (size_t i = 0; i < stage_ms.size(); ++i) {
    std::snprintf(line, sizeof line, "  %-20s %9.1f ms\n", build_stage_name(BuildStage(i)), stage_ms[i]);
    s += line;
  }
  return s;
}

namespace {

// Rough shares of the total time per stage, for the progress bar.
constexpr float kStart[] = {0.0f, 0.1f, 0.2f, 0.9f, 0.95f, 0.98f, 1.0f};

void estimate_from_rays(Topology& t, std::span<const glm::vec3> soup, const RayQueries& rays,
                        const CancelCheck& cancelled) {
  // The gates first: the passages are estimated between the clusters they leave unjoined.
  if (rays.first_hit && !t.occluders_estimated) {
    fit_gates_to_surfaces(t.grid.shape, rays.first_hit, t.gates, cancelled);
    // A second opening whose skeleton gate was left out for being narrow joins nothing.
    t.component = gate_components(t.cluster_count, t.gates);
    std::erase_if(t.gates, [&](const Gate& g) { return g.needs_ray() && !t.joined(g.clusters[0], g.clusters[1]); });
    t.occluders = estimate_occluders(t, soup, rays.first_hit, cancelled);
    t.occluders_estimated = true;
  }
  if (rays.clear && !t.passages_estimated) {
    t.passages = estimate_passages(t, soup, rays.clear, cancelled);
    t.passages_estimated = true;
  }
}

}  // namespace

Topology build(std::span<const glm::vec3> soup, const Settings& settings, const Progress& progress,
               const RayQueries& rays) {
  Topology t;
  auto stage_start = std::chrono::steady_clock::now();
  BuildStage current = BuildStage::Voxelize;
  const auto begin = [&](BuildStage stage) {
    const auto now = std::chrono::steady_clock::now();
    if (stage != BuildStage::Voxelize) {
      t.stage_ms[size_t(current)] = std::chrono::duration<double, std::milli>(now - stage_start).count();
    }
    stage_start = now;
    current = stage;
    if (progress && stage != BuildStage::Count && !progress(stage, kStart[size_t(stage)])) throw Cancelled{};
  };
  const CancelCheck cancelled = [&] { return progress && !progress(current, kStart[size_t(current)]); };

  begin(BuildStage::Voxelize);
  const int resolution = std::clamp(settings.resolution, 1, kMaxResolution);
  t.grid = voxelize(soup, fit_grid(soup, resolution, settings.margin));
  begin(BuildStage::DistanceTransform);
  const std::vector<uint32_t> d2 = squared_distance_transform(t.grid);
  begin(BuildStage::Thinning);
  t.skeleton = skeletonize(t.grid, d2, cancelled);
  begin(BuildStage::Segmentation);
  const float alpha = std::clamp(settings.alpha, 0.0f, 1.0f);
  t.segmented = segment(t.skeleton, alpha);
  begin(BuildStage::Clusters);
  t.cluster_of = visibility_clusters(t.skeleton, t.segmented, alpha, &t.cluster_count);
  begin(BuildStage::Gates);
  t.gates = visibility_gates(t.skeleton, t.segmented, t.cluster_of);
  t.node_cluster = node_clusters(t.skeleton, t.segmented, t.cluster_of);
  std::vector<uint32_t> voxel_cluster(t.skeleton.voxel_node.size());
  for (std::size_t i = 0; i < voxel_cluster.size(); ++i) voxel_cluster[i] = t.cluster_of_node(t.skeleton.voxel_node[i]);
  fit_gates_to_boundaries(t.grid, voxel_cluster, t.gates);
  add_boundary_gates(t.grid.shape, voxel_cluster, t.gates);
  t.component = gate_components(t.cluster_count, t.gates);
  estimate_from_rays(t, soup, rays, cancelled);
  begin(BuildStage::Count);
  return t;
}

Topology with_ray_estimates(Topology base, std::span<const glm::vec3> soup, const RayQueries& rays,
                            const Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  const auto gates = std::size_t(BuildStage::Gates);
  const CancelCheck cancelled = [&] { return progress && !progress(BuildStage::Gates, kStart[gates]); };
  if (cancelled()) throw Cancelled{};
  estimate_from_rays(base, soup, rays, cancelled);
  base.stage_ms[gates] += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return base;
}

std::vector<uint32_t> voxel_clusters_split_at_gates(const Topology& t) {
  const GridShape& shape = t.grid.shape;
  std::vector<uint32_t> clusters(shape.padded_count(), kNoNode);
  for (std::size_t i = 0; i < clusters.size() && i < t.skeleton.voxel_node.size(); ++i)
    clusters[i] = t.cluster_of_node(t.skeleton.voxel_node[i]);
  static constexpr std::array<glm::ivec3, 6> kFaces{
      {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}};
  const double h = shape.voxel_size;
  for (const Gate& gate : t.gates) {
    if (gate.kind != Gate::Kind::kSkeleton || gate.clusters[0] >= t.cluster_count ||
        gate.clusters[1] >= t.cluster_count)
      continue;
    const glm::dvec3 centre(gate.centre), n(gate.normal), u(gate.axis_u), w = glm::cross(n, u);
    const double reach = std::hypot(double(gate.half_u), double(gate.half_v)) + 2.0 * h;
    const glm::ivec3 lo = glm::max(shape.voxel_at(centre - reach), glm::ivec3(0)),
                     hi = glm::min(shape.voxel_at(centre + reach), shape.dims - 1);
    for (int side = 0; side < 2; ++side) {
      const uint32_t from = gate.clusters[side], to = gate.clusters[1 - side];
      const double sign = side == 0 ? 1.0 : -1.0;  // the normal points from clusters[0] to clusters[1]
      const auto past = [&](glm::ivec3 v) {
        const glm::dvec3 d = shape.centre(v) - centre;
        return shape.inside(v) && clusters[shape.index(v)] == from && sign * glm::dot(d, n) > 0.0 &&
               glm::length(d) <= reach;
      };
      // Seeds: `from`'s voxels just past the plane, in the opening.
      std::vector<glm::ivec3> queue;
      for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
          for (int x = lo.x; x <= hi.x; ++x) {
            const glm::ivec3 v(x, y, z);
            const glm::dvec3 d = shape.centre(v) - centre;
            if (past(v) && sign * glm::dot(d, n) <= 1.5 * h && std::abs(glm::dot(d, u)) <= double(gate.half_u) + h &&
                std::abs(glm::dot(d, w)) <= double(gate.half_v) + h) {
              clusters[shape.index(v)] = to;
              queue.push_back(v);
            }
          }
      for (std::size_t head = 0; head < queue.size(); ++head)
        for (const glm::ivec3& o : kFaces)
          if (const glm::ivec3 v = queue[head] + o; past(v)) {
            clusters[shape.index(v)] = to;
            queue.push_back(v);
          }
    }
  }
  return clusters;
}

}  // namespace bounce::topology
