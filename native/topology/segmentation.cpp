#include "segmentation.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <span>
#include <tuple>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

namespace bounce::topology {

namespace {

constexpr std::size_t kMaxGateCells = 1u << 18;  // of a gate's opening: more than a 256^3 grid's section
constexpr int kPlaneSearchSteps = 4;             // half voxels either side of a gate's neck, at most its ball
constexpr double kMaxGateReach = 4.0;            // of an opening from its neck, in neck balls

// A unit vector orthogonal to the unit vector n.
glm::vec3 perpendicular(glm::vec3 n) {
  return glm::normalize(
      glm::cross(n, std::abs(n.x) < 0.9f ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0.0f, 1.0f, 0.0f)));
}

// The rectangle around points of a plane, along their main axis (that of their second moments about their mean):
// its centre, its unit axis, and the points' largest distances from the centre along the axis and across it.
struct PlaneRectangle {
  glm::dvec2 centre{0.0}, axis{1.0, 0.0};
  double half_u = 0.0, half_v = 0.0;
};

PlaneRectangle rectangle_around(std::span<const glm::dvec2> points) {
  PlaneRectangle r;
  for (const glm::dvec2& p : points) r.centre += p;
  r.centre /= double(points.size());
  double xx = 0.0, xy = 0.0, yy = 0.0;
  for (const glm::dvec2& p : points) {
    const glm::dvec2 d = p - r.centre;
    xx += d.x * d.x, xy += d.x * d.y, yy += d.y * d.y;
  }
  const double angle = 0.5 * std::atan2(2.0 * xy, xx - yy);
  r.axis = glm::dvec2(std::cos(angle), std::sin(angle));
  const glm::dvec2 other(-r.axis.y, r.axis.x);
  for (const glm::dvec2& p : points) {
    r.half_u = std::max(r.half_u, std::abs(glm::dot(p - r.centre, r.axis)));
    r.half_v = std::max(r.half_v, std::abs(glm::dot(p - r.centre, other)));
  }
  return r;
}

// A plane with orthonormal axes, and the world length of its coordinates' unit.
struct PlaneFrame {
  glm::dvec3 origin, normal, t, w;
  double unit = 1.0;
};

// The gate's rectangle: r, in the frame's coordinates, widened by `margin` (world units) on every side.
void place_rectangle(Gate& gate, const PlaneRectangle& r, const PlaneFrame& frame, double margin) {
  gate.centre = glm::vec3(frame.origin + (r.centre.x * frame.t + r.centre.y * frame.w) * frame.unit);
  gate.normal = glm::vec3(frame.normal);
  gate.axis_u = glm::vec3(r.axis.x * frame.t + r.axis.y * frame.w);
  gate.half_u = float(r.half_u * frame.unit + margin);
  gate.half_v = float(r.half_v * frame.unit + margin);
  gate.radius = std::sqrt(gate.half_u * gate.half_u + gate.half_v * gate.half_v);
}

// Calls visit(face centre, axis, a, b) for every face between an empty voxel of cluster a and its neighbour of
// cluster b != a one step up `axis`.
template <typename Visit>
void for_each_boundary_face(const GridShape& shape, const std::vector<uint32_t>& voxel_cluster, Visit&& visit) {
  const glm::ivec3 padded = shape.padded();
  const std::ptrdiff_t strides[3] = {1, padded.x, std::ptrdiff_t(padded.x) * padded.y};
  for (std::size_t i = 0; i < voxel_cluster.size(); ++i) {
    const uint32_t a = voxel_cluster[i];
    if (a == kNoNode) continue;
    for (int axis = 0; axis < 3; ++axis) {
      const std::size_t j = i + std::size_t(strides[axis]);
      if (j >= voxel_cluster.size()) continue;
      const uint32_t b = voxel_cluster[j];
      if (b == kNoNode || b == a) continue;
      visit(0.5 * (shape.centre(shape.voxel_of_index(i)) + shape.centre(shape.voxel_of_index(j))), axis, a, b);
    }
  }
}

// Distance from p to the straight line through a and b (to a itself when they coincide).
float distance_to_line(glm::vec3 p, glm::vec3 a, glm::vec3 b) {
  const glm::vec3 ab = b - a;
  const float length2 = glm::dot(ab, ab);
  if (length2 <= 0.0f) return glm::distance(p, a);
  return glm::length(glm::cross(p - a, ab)) / std::sqrt(length2);
}

// The skeleton's lines: node sequences whose ends are topology nodes and whose inner nodes are not.
std::vector<std::vector<uint32_t>> lines_between(const Graph& graph, const std::vector<NodeKind>& kind) {
  std::vector<std::vector<uint32_t>> lines;
  std::vector<uint8_t> walked(graph.node_count(), 0);
  for (uint32_t t = 0; t < graph.node_count(); ++t) {
    if (kind[t] != NodeKind::Topology) continue;
    for (uint32_t w : graph.neighbours(t)) {
      if (kind[w] == NodeKind::Topology) {
        if (t < w) lines.push_back({t, w});
        continue;
      }
      if (walked[w]) continue;
      std::vector<uint32_t> line{t};
      uint32_t previous = t, current = w;
      while (kind[current] != NodeKind::Topology) {
        walked[current] = 1;
        line.push_back(current);
        const auto next = graph.neighbours(current);
        const uint32_t following = next[0] == previous ? next[1] : next[0];
        previous = current;
        current = following;
      }
      line.push_back(current);
      lines.push_back(std::move(line));
    }
  }
  return lines;
}

// Splits line[a..b] at the inner node `pick` chooses (or none: -1), recursively, marking it `as`.
template <typename Pick>
void split(const std::vector<uint32_t>& line, std::vector<NodeKind>& kind, NodeKind as, Pick&& pick) {
  std::vector<std::pair<int, int>> pieces;
  int previous = 0;
  for (int i = 1; i < int(line.size()); ++i) {
    if (i + 1 < int(line.size()) && kind[line[size_t(i)]] == NodeKind::Removed) continue;
    pieces.emplace_back(previous, i);
    previous = i;
  }
  while (!pieces.empty()) {
    const auto [a, b] = pieces.back();
    pieces.pop_back();
    if (b - a < 2) continue;
    const int at = pick(a, b);
    if (at < 0) continue;
    kind[line[size_t(at)]] = as;
    pieces.emplace_back(a, at);
    pieces.emplace_back(at, b);
  }
}

}  // namespace

SegmentedSkeleton segment(const Skeleton& skeleton, float alpha) {
  const Graph& graph = skeleton.graph;
  const size_t n = graph.node_count();
  SegmentedSkeleton out;
  out.kind.assign(n, NodeKind::Removed);
  for (uint32_t v = 0; v < n; ++v)
    if (graph.degree(v) != 2) out.kind[v] = NodeKind::Topology;
  size_t component_count = 0;
  const std::vector<uint32_t> component = graph_components(graph, &component_count);
  std::vector<uint32_t> widest(component_count, kNoNode);
  std::vector<uint8_t> anchored(component_count, 0);
  for (uint32_t v = 0; v < n; ++v) {
    const uint32_t c = component[v];
    anchored[c] |= out.kind[v] == NodeKind::Topology;
    if (widest[c] == kNoNode || skeleton.radius[v] > skeleton.radius[widest[c]]) widest[c] = v;
  }
  for (size_t c = 0; c < component_count; ++c)
    if (!anchored[c]) out.kind[widest[c]] = NodeKind::Topology;

  const auto& p = skeleton.position;
  const auto& r = skeleton.radius;
  const std::vector<std::vector<uint32_t>> lines = lines_between(graph, out.kind);
  for (const auto& line : lines) {
    split(line, out.kind, NodeKind::Curvature, [&](int a, int b) {
      int best = -1;
      float best_curvature = 1.0f;
      for (int i = a + 1; i < b; ++i) {
        const uint32_t v = line[size_t(i)];
        const float curvature = distance_to_line(p[v], p[line[size_t(a)]], p[line[size_t(b)]]) / r[v];
        if (curvature > best_curvature) best_curvature = curvature, best = i;
      }
      return best;
    });
  }
  for (const auto& line : lines) {
    split(line, out.kind, NodeKind::Coverage, [&](int a, int b) {
      const uint32_t ea = line[size_t(a)], eb = line[size_t(b)];
      int best = -1;
      float most_outside = 0.0f;
      for (int i = a + 1; i < b; ++i) {
        const uint32_t v = line[size_t(i)];
        const float outside = std::min(glm::distance(p[v], p[ea]) - r[ea], glm::distance(p[v], p[eb]) - r[eb]);
        if (outside > most_outside) most_outside = outside, best = i;
      }
      return best;
    });
  }

  for (const auto& line : lines) {
    split(line, out.kind, NodeKind::Neck, [&](int a, int b) {
      int best = a + 1;
      for (int i = a + 2; i < b; ++i)
        if (r[line[size_t(i)]] < r[line[size_t(best)]]) best = i;
      const float ends = std::min(r[line[size_t(a)]], r[line[size_t(b)]]);
      return r[line[size_t(best)]] < (1.0f - alpha) * ends ? best : -1;
    });
  }

  // Cycles: a loop needs two inner nodes, a second line between the same two nodes one.
  std::set<std::pair<uint32_t, uint32_t>> edges;
  std::vector<std::vector<int>> kept(lines.size());
  for (size_t l = 0; l < lines.size(); ++l) {
    const auto& line = lines[l];
    const int last = int(line.size()) - 1;
    int inner = 0;
    for (int i = 1; i < last; ++i) inner += out.kind[line[size_t(i)]] != NodeKind::Removed;
    if (line.front() == line.back() && inner < 2) {
      out.kind[line[size_t(std::max(1, last / 3))]] = NodeKind::Topology;
      out.kind[line[size_t(std::max(1, 2 * last / 3))]] = NodeKind::Topology;
    } else if (inner == 0 && last >= 2) {
      const auto key = std::minmax(line.front(), line.back());
      if (!edges.insert(key).second) out.kind[line[size_t(last / 2)]] = NodeKind::Topology;
    }
    for (int i = 0; i <= last; ++i)
      if (out.kind[line[size_t(i)]] != NodeKind::Removed) kept[l].push_back(i);
  }

  out.segmented_of.assign(n, kNoNode);
  for (uint32_t v = 0; v < n; ++v) {
    if (out.kind[v] == NodeKind::Removed) continue;
    out.segmented_of[v] = uint32_t(out.original.size());
    out.original.push_back(v);
  }
  for (size_t l = 0; l < lines.size(); ++l) {
    const auto& line = lines[l];
    for (size_t k = 0; k + 1 < kept[l].size(); ++k) {
      const int a = kept[l][k], b = kept[l][k + 1];
      const uint32_t sa = out.segmented_of[line[size_t(a)]], sb = out.segmented_of[line[size_t(b)]];
      if (sa != sb) {
        out.edges.emplace_back(sa, sb);
        out.edge_paths.emplace_back(line.begin() + a, line.begin() + b + 1);
      }
      for (int i = a + 1; i < b; ++i) {
        const uint32_t v = line[size_t(i)];
        out.segmented_of[v] =
            glm::distance(p[v], p[line[size_t(a)]]) <= glm::distance(p[v], p[line[size_t(b)]]) ? sa : sb;
      }
    }
  }
  out.graph = Graph::from_edges(out.original.size(), out.edges);
  return out;
}

std::vector<uint32_t> visibility_clusters(const Skeleton& skeleton, const SegmentedSkeleton& segmented, float alpha,
                                          uint32_t* count) {
  const size_t n = segmented.original.size();
  const auto position = [&](uint32_t s) { return skeleton.position[segmented.original[s]]; };
  const auto radius = [&](uint32_t s) { return skeleton.radius[segmented.original[s]]; };
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return radius(a) > radius(b); });

  const auto similar = [&](uint32_t s, float largest) {
    return segmented.kind[segmented.original[s]] != NodeKind::Curvature &&
           std::abs(radius(s) - largest) <= alpha * largest;
  };
  std::vector<uint32_t> cluster(n, kNoNode), stack, ball;
  std::vector<uint32_t> seen(n, kNoNode);  // the node whose ball walk last reached it
  uint32_t clusters = 0;
  for (uint32_t seed : order) {
    if (cluster[seed] != kNoNode) continue;
    const uint32_t c = clusters++;
    float largest = radius(seed);
    cluster[seed] = c;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const uint32_t m = stack.back();
      stack.pop_back();
      largest = std::max(largest, radius(m));
      // A curvature node spreads its cluster no more than it joins one: a bend seeds a cluster of its own.
      const bool bend = segmented.kind[segmented.original[m]] == NodeKind::Curvature;
      for (uint32_t w : segmented.graph.neighbours(m)) {
        if (bend || cluster[w] != kNoNode || !similar(w, largest)) continue;
        cluster[w] = c;
        stack.push_back(w);
      }
      // The nodes inside m's maximal ball that a walk from m reaches without leaving it.
      seen[m] = m;
      ball.assign(1, m);
      while (!ball.empty()) {
        const uint32_t u = ball.back();
        ball.pop_back();
        for (uint32_t w : segmented.graph.neighbours(u)) {
          if (seen[w] == m || glm::distance(position(w), position(m)) > radius(m)) continue;
          seen[w] = m;
          ball.push_back(w);
          if (cluster[w] != kNoNode) continue;
          cluster[w] = c;
          if (similar(w, largest)) stack.push_back(w);
        }
      }
    }
  }
  // A cluster with no local maximum of the maximal ball is a passage between clusters (the approach to a
  // doorway, whose balls grow toward both rooms): its nodes follow the steepest ascent of the radius into the
  // clusters it joins.
  std::vector<uint8_t> kept(clusters, 0);
  const auto steepest = [&](uint32_t s) {
    uint32_t best = s;
    for (uint32_t w : segmented.graph.neighbours(s))
      if (radius(w) > radius(best)) best = w;
    return best;
  };
  for (uint32_t s = 0; s < n; ++s)
    if (steepest(s) == s) kept[cluster[s]] = 1;
  std::vector<uint32_t> merged(n);
  for (uint32_t s = 0; s < n; ++s) {
    uint32_t top = s;
    while (!kept[cluster[top]]) top = steepest(top);
    merged[s] = cluster[top];
  }
  std::vector<uint32_t> renumber(clusters, kNoNode);
  uint32_t used = 0;
  for (uint32_t& c : merged) {
    if (renumber[c] == kNoNode) renumber[c] = used++;
    c = renumber[c];
  }
  if (count) *count = used;
  return merged;
}

namespace {

// The node of smallest maximal ball along a skeleton path, where a gate on it sits.
size_t neck_of(const Skeleton& skeleton, const std::vector<uint32_t>& path) {
  size_t neck = 0;
  for (size_t i = 1; i < path.size(); ++i)
    if (skeleton.radius[path[i]] < skeleton.radius[path[neck]]) neck = i;
  return neck;
}

}  // namespace

std::vector<uint32_t> node_clusters(const Skeleton& skeleton, const SegmentedSkeleton& segmented,
                                    const std::vector<uint32_t>& cluster_of) {
  std::vector<uint32_t> clusters(segmented.segmented_of.size(), kNoNode);
  for (size_t node = 0; node < clusters.size(); ++node)
    if (segmented.segmented_of[node] != kNoNode) clusters[node] = cluster_of[segmented.segmented_of[node]];
  for (size_t e = 0; e < segmented.edges.size(); ++e) {
    const auto [a, b] = segmented.edges[e];
    if (cluster_of[a] == cluster_of[b]) continue;
    const std::vector<uint32_t>& path = segmented.edge_paths[e];
    const size_t neck = neck_of(skeleton, path);
    for (size_t i = 0; i < path.size(); ++i) clusters[path[i]] = cluster_of[i <= neck ? a : b];
  }
  return clusters;
}

std::vector<Gate> visibility_gates(const Skeleton& skeleton, const SegmentedSkeleton& segmented,
                                   const std::vector<uint32_t>& cluster_of) {
  std::vector<Gate> gates;
  for (size_t e = 0; e < segmented.edges.size(); ++e) {
    const auto [a, b] = segmented.edges[e];
    if (cluster_of[a] == cluster_of[b]) continue;
    const std::vector<uint32_t>& path = segmented.edge_paths[e];
    const size_t neck = neck_of(skeleton, path);
    // The path's direction at the neck, over a few nodes so voxel steps do not tilt it.
    const size_t before = neck >= 2 ? neck - 2 : 0, after = std::min(path.size() - 1, neck + 2);
    glm::vec3 along = skeleton.position[path[after]] - skeleton.position[path[before]];
    if (glm::dot(along, along) <= 0.0f) along = skeleton.position[path.back()] - skeleton.position[path.front()];
    Gate gate;
    gate.centre = skeleton.position[path[neck]];
    gate.normal = glm::normalize(along);
    gate.radius = skeleton.radius[path[neck]];
    gate.axis_u = perpendicular(gate.normal);
    gate.half_u = gate.half_v = gate.radius;
    gate.clusters = {cluster_of[a], cluster_of[b]};
    gates.push_back(gate);
  }
  return gates;
}

void fit_gates_to_boundaries(const VoxelGrid& grid, const std::vector<uint32_t>& voxel_cluster,
                             std::vector<Gate>& gates) {
  const GridShape& shape = grid.shape;
  if (gates.empty() || voxel_cluster.size() != shape.padded_count()) return;
  std::map<std::pair<uint32_t, uint32_t>, std::vector<std::size_t>> gates_of_pair;
  for (std::size_t g = 0; g < gates.size(); ++g)
    gates_of_pair[std::minmax(gates[g].clusters[0], gates[g].clusters[1])].push_back(g);
  // The boundary surface between the two clusters' voxels, as the sum of its faces' normals (from the gate's first
  // cluster to its second), each face to the nearest gate of its pair: the opening's orientation, whatever the
  // voxel steps (a single edge of the skeleton tilts by up to 27 degrees).
  std::vector<glm::dvec3> orientation(gates.size(), glm::dvec3(0.0));
  for_each_boundary_face(shape, voxel_cluster, [&](glm::dvec3 face, int axis, uint32_t a, uint32_t b) {
    const auto found = gates_of_pair.find(std::minmax(a, b));
    if (found == gates_of_pair.end()) return;
    std::size_t nearest = found->second.front();
    for (std::size_t g : found->second)
      if (glm::distance(face, glm::dvec3(gates[g].centre)) < glm::distance(face, glm::dvec3(gates[nearest].centre)))
        nearest = g;
    glm::dvec3 normal(0.0);
    normal[axis] = gates[nearest].clusters[0] == a ? 1.0 : -1.0;
    orientation[nearest] += normal;
  });
  for (std::size_t g = 0; g < gates.size(); ++g) {
    Gate& gate = gates[g];
    // The opening: the empty voxels of a plane through the neck connected to it within the gate's two clusters,
    // found cell by cell in the plane (cells a voxel apart). In a doorway the plane runs inside the wall, whose
    // voxels bound the opening; where a room is split in two, the room's walls bound it, and a window in them
    // does not let it spread outside (the outside is another cluster). The plane is the narrowest such section near the
    // neck: facing as the boundary's faces do on the whole, as the skeleton's path, or along a grid axis (the faces are
    // axis-aligned, and a few of them along the floor tilt their sum), at half-voxel offsets either side of the neck
    // (which may sit off a wall's layer of voxels). The neck's maximal ball bounds the search: the plane moves no
    // further than it, and the opening reaches no further than kMaxGateReach of it (a window whose blinds leave only
    // gaps of voxels would otherwise take the whole wall around it).
    const double ball = std::max(double(gate.radius), 0.5 * shape.voxel_size);
    const int steps = std::min(kPlaneSearchSteps, int(2.0 * ball / shape.voxel_size));
    const double reach = kMaxGateReach * ball / shape.voxel_size;  // in cells
    const double length = glm::length(orientation[g]);
    const glm::dvec3 along = length > 0.0 ? orientation[g] / length : glm::dvec3(gate.normal);
    std::vector<glm::ivec2> cells;
    glm::dvec3 origin(gate.centre), n(along), t(0.0), w(0.0);
    for (glm::dvec3 candidate :
         {along, glm::dvec3(gate.normal), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)}) {
      if (glm::dot(candidate, along) < 0.0) candidate = -candidate;  // from clusters[0]'s side to clusters[1]'s
      const glm::dvec3 ct(perpendicular(glm::vec3(candidate))), cw = glm::cross(candidate, ct);
      for (int step = -steps; step <= steps; ++step) {
        const glm::dvec3 plane = glm::dvec3(gate.centre) + candidate * (0.5 * step * shape.voxel_size);
        const auto empty = [&](glm::ivec2 cell) {
          if (double(cell.x) * cell.x + double(cell.y) * cell.y > reach * reach) return false;
          const glm::ivec3 v = shape.voxel_at(plane + (double(cell.x) * ct + double(cell.y) * cw) * shape.voxel_size);
          if (!shape.inside(v) || grid.solid[shape.index(v)]) return false;
          const uint32_t cluster = voxel_cluster[shape.index(v)];
          return cluster == gate.clusters[0] || cluster == gate.clusters[1];
        };
        if (!empty({0, 0})) continue;
        std::set<std::pair<int, int>> seen{{0, 0}};
        std::vector<glm::ivec2> open{{0, 0}}, found;
        const std::size_t limit = cells.empty() ? kMaxGateCells : cells.size();
        while (!open.empty() && found.size() < limit) {
          const glm::ivec2 c = open.back();
          open.pop_back();
          found.push_back(c);
          for (const glm::ivec2& d : {glm::ivec2(1, 0), glm::ivec2(-1, 0), glm::ivec2(0, 1), glm::ivec2(0, -1)})
            if (seen.insert({c.x + d.x, c.y + d.y}).second && empty(c + d)) open.push_back(c + d);
        }
        if (open.empty() && (cells.empty() || found.size() < cells.size())) {
          cells = std::move(found);
          origin = plane, n = candidate, t = ct, w = cw;
        }
      }
    }
    if (cells.empty()) continue;
    // The rectangle around the cells, along their main axis: each cell stands for a voxel-sized square, and the
    // opening reaches on average half a voxel beyond its empty cells (the conservative voxelization marks solid
    // every voxel a jamb passes through, wherever in it the jamb's face lies), so a voxel beyond the outermost
    // cells' centres. Ending at the empty cells lost the light along the opening's edges (a doorway 2 m by 3 m
    // at 0.16 m voxels passed 0.87 of the shadow rays' light into the next room, 0.92 now).
    const std::vector<glm::dvec2> points(cells.begin(), cells.end());
    place_rectangle(gate, rectangle_around(points), {origin, n, t, w, shape.voxel_size}, shape.voxel_size);
  }
}

namespace {

// Whether a boundary face lies in a gate's opening: inside its rectangle, and near enough its plane: the plane
// lies up to kPlaneSearchSteps half voxels off the neck, the boundary a voxel off it.
bool in_gate_opening(const Gate& gate, glm::dvec3 face, double voxel) {
  const glm::dvec3 offset = face - glm::dvec3(gate.centre);
  const glm::dvec3 n(gate.normal), u(gate.axis_u), v = glm::cross(n, u);
  return std::abs(glm::dot(offset, n)) <= (0.5 * kPlaneSearchSteps + 1.0) * voxel &&
         std::abs(glm::dot(offset, u)) <= gate.half_u && std::abs(glm::dot(offset, v)) <= gate.half_v;
}

struct BoundaryFace {
  glm::dvec3 centre;
  glm::ivec3 key;     // the centre in half voxels: faces of one piece of boundary lie at most a voxel apart
  glm::dvec3 normal;  // from the pair's first cluster to its second
};

// The pieces of a boundary: faces joined through neighbours at most a voxel apart (an edge or a corner shared).
std::vector<std::vector<BoundaryFace>> boundary_pieces(const std::vector<BoundaryFace>& faces) {
  std::map<std::tuple<int, int, int>, std::size_t> index;
  for (std::size_t i = 0; i < faces.size(); ++i) index[{faces[i].key.x, faces[i].key.y, faces[i].key.z}] = i;
  std::vector<uint8_t> taken(faces.size(), 0);
  std::vector<std::vector<BoundaryFace>> pieces;
  std::vector<std::size_t> stack;
  for (std::size_t seed = 0; seed < faces.size(); ++seed) {
    if (taken[seed]) continue;
    taken[seed] = 1;
    stack.assign(1, seed);
    std::vector<BoundaryFace>& piece = pieces.emplace_back();
    while (!stack.empty()) {
      const BoundaryFace& face = faces[stack.back()];
      stack.pop_back();
      piece.push_back(face);
      for (int dz = -2; dz <= 2; ++dz)
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) {
            if (dx * dx + dy * dy + dz * dz > 4) continue;
            const auto found = index.find({face.key.x + dx, face.key.y + dy, face.key.z + dz});
            if (found == index.end() || taken[found->second]) continue;
            taken[found->second] = 1;
            stack.push_back(found->second);
          }
    }
  }
  return pieces;
}

}  // namespace

void add_boundary_gates(const GridShape& shape, const std::vector<uint32_t>& voxel_cluster, std::vector<Gate>& gates) {
  std::map<std::pair<uint32_t, uint32_t>, std::vector<std::size_t>> gates_of_pair;
  for (std::size_t g = 0; g < gates.size(); ++g)
    gates_of_pair[std::minmax(gates[g].clusters[0], gates[g].clusters[1])].push_back(g);
  const glm::dvec3 origin = shape.centre(glm::ivec3(0));
  std::map<std::pair<uint32_t, uint32_t>, std::vector<BoundaryFace>> boundaries;
  for_each_boundary_face(shape, voxel_cluster, [&](glm::dvec3 face, int axis, uint32_t a, uint32_t b) {
    const auto pair = std::minmax(a, b);
    glm::dvec3 normal(0.0);
    normal[axis] = a == pair.first ? 1.0 : -1.0;
    boundaries[pair].push_back({face, glm::ivec3(glm::round(2.0 * (face - origin) / shape.voxel_size)), normal});
  });
  for (const auto& [pair, faces] : boundaries) {
    // Two clusters no gate joins get one rectangle around all their faces; those of a pair a gate joins, per piece
    // of their boundary, one around the piece's faces outside the gates' openings. Per piece, not per run of such
    // faces: the staircase around an opening leaves fragments of a few faces (the Cornell box: 403 of 2-4 faces),
    // each a gate every walk tries, which doubled its render time.
    const auto gated = gates_of_pair.find(pair);
    const auto covered = [&](const BoundaryFace& face) {
      return gated != gates_of_pair.end() &&
             std::any_of(gated->second.begin(), gated->second.end(),
                         [&](std::size_t g) { return in_gate_opening(gates[g], face.centre, shape.voxel_size); });
    };
    for (std::vector<BoundaryFace> piece :
         gated != gates_of_pair.end() ? boundary_pieces(faces) : std::vector<std::vector<BoundaryFace>>{faces}) {
      std::erase_if(piece, covered);
      if (piece.empty()) continue;
      glm::dvec3 sum(0.0), centre(0.0);
      for (const BoundaryFace& face : piece) sum += face.normal, centre += face.centre;
      const double length = glm::length(sum);
      // Faces whose normals cancel (a cluster wrapped around another) have no plane a rectangle could stand for.
      if (!(length > 0.0)) continue;
      const glm::dvec3 n = sum / length;
      centre /= double(piece.size());
      // The rectangle around the faces projected on the plane through their mean.
      const glm::dvec3 t(perpendicular(glm::vec3(n))), w = glm::cross(n, t);
      std::vector<glm::dvec2> points;
      points.reserve(piece.size());
      for (const BoundaryFace& face : piece)
        points.emplace_back(glm::dot(face.centre - centre, t), glm::dot(face.centre - centre, w));
      Gate gate;
      place_rectangle(gate, rectangle_around(points), {centre, n, t, w, 1.0}, 0.5 * shape.voxel_size);
      gate.clusters = {pair.first, pair.second};
      gate.kind = gated != gates_of_pair.end() ? Gate::Kind::kSecondOpening : Gate::Kind::kBoundary;
      gates.push_back(gate);
    }
  }
}

}  // namespace bounce::topology
