#include "skeleton.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <unordered_map>

#include <glm/common.hpp>

#include "local_topology.h"

namespace bounce::topology {

namespace {

enum : uint8_t { kEmpty = 0, kSolid = 1, kDeleted = 2, kAnchor = 4, kQueued = 8 };
constexpr uint8_t kBackground = kSolid | kDeleted;

// Union-find over padded cells, path halving; the root of the padding is cell 0.
struct CellSets {
  std::vector<uint32_t> parent;
  uint32_t find(uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void unite(uint32_t a, uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

bool is_padding(const GridShape& shape, size_t i) { return !shape.inside(shape.voxel_of_index(i)); }

// The solid's 6-connected components, the padding one of them.
CellSets solid_components(const VoxelGrid& grid) {
  const GridShape& shape = grid.shape;
  const glm::ivec3 p = shape.padded();
  CellSets sets{std::vector<uint32_t>(shape.padded_count())};
  for (size_t i = 0; i < sets.parent.size(); ++i) sets.parent[i] = is_padding(shape, i) ? 0u : uint32_t(i);
  const size_t back[3] = {1, size_t(p.x), size_t(p.x) * size_t(p.y)};
  for (int z = 0; z < shape.dims.z; ++z)
    for (int y = 0; y < shape.dims.y; ++y)
      for (int x = 0; x < shape.dims.x; ++x) {
        const size_t i = shape.index({x, y, z});
        if (!grid.solid[i]) continue;
        for (size_t b : back)
          if (grid.solid[i - b]) sets.unite(uint32_t(i), uint32_t(i - b));
      }
  return sets;
}

constexpr uint32_t kIsthmusPersistence = 8;

double radius_in_voxels(uint32_t squared_distance) { return std::max(0.5, std::sqrt(double(squared_distance)) - 0.5); }

// Distance-ordered thinning; returns the cell states (skeleton cells: neither solid nor deleted).
std::vector<uint8_t> thin(const VoxelGrid& grid, std::span<const uint32_t> d2, const CancelCheck& cancelled) {
  const GridShape& shape = grid.shape;
  const auto strides = shape.neighbour_strides();
  std::vector<uint8_t> state(grid.solid.size());
  for (size_t i = 0; i < state.size(); ++i) state[i] = grid.solid[i] ? kSolid : kEmpty;
  CellSets background = solid_components(grid);

  // Buckets by rank of squared distance: the queue pops the cell nearest to the solid first. The ranks come
  // from a table over the distances that occur, so a push costs one lookup.
  uint32_t farthest = 0;
  for (size_t i = 0; i < state.size(); ++i)
    if (state[i] == kEmpty) farthest = std::max(farthest, d2[i]);
  std::vector<uint32_t> rank_of(size_t(farthest) + 1, 0);
  for (size_t i = 0; i < state.size(); ++i)
    if (state[i] == kEmpty) rank_of[d2[i]] = 1;
  uint32_t ranks = 0;
  for (uint32_t& r : rank_of) r = r ? ranks++ : 0;
  const auto rank = [&](size_t i) { return size_t(rank_of[d2[i]]); };
  std::vector<std::vector<uint32_t>> buckets(ranks);
  const uint32_t faces = face_neighbours();
  for (size_t i = 0; i < state.size(); ++i) {
    if (state[i] != kEmpty) continue;
    for (uint32_t f = faces; f; f &= f - 1) {
      if (state[i + strides[size_t(std::countr_zero(f))]] & kBackground) {
        buckets[rank(i)].push_back(uint32_t(i));
        state[i] |= kQueued;
        break;
      }
    }
  }

  // Isthmus persistence (Couprie and Bertrand 2014): a cell becomes an anchor of the skeleton only once it has
  // been a 1-D isthmus for kIsthmusPersistence rounds; the short curves that eroding sheets leave for a round or
  // two are eaten from their ends first.
  std::unordered_map<uint32_t, uint32_t> isthmus_birth;
  uint32_t rounds = 0;

  // Whether cell i may go now: T26 = 1, and its background neighbours lie in distinct components of the
  // whole background, so removing it merges them (opens a cavity) and never closes a loop around the empty
  // space (for one component: a simple point). Anchors it when it is an isthmus.
  const auto removable = [&](uint32_t i) {
    uint32_t object = 0;
    for (size_t k = 0; k < 26; ++k)
      if (!(state[i + strides[k]] & kBackground)) object |= 1u << k;
    const LocalTopology local = classify_neighbourhood(object);
    // A cell is looked at again only when a neighbour goes, so one that was an isthmus when last seen has been
    // one ever since.
    if (local.isthmus()) {
      const uint32_t born = isthmus_birth.emplace(i, rounds).first->second;
      if (rounds - born >= kIsthmusPersistence) state[i] = kAnchor;
      return false;
    }
    if (const auto it = isthmus_birth.find(i); it != isthmus_birth.end()) {
      if (rounds - it->second >= kIsthmusPersistence) {
        state[i] = kAnchor;
        return false;
      }
      isthmus_birth.erase(it);
    }
    if (local.object_components != 1 || local.background_components == 0) return false;
    uint32_t roots[6];
    for (int c = 0; c < local.background_components; ++c) {
      const uint32_t face = local.background_masks[size_t(c)] & faces;
      roots[c] = background.find(uint32_t(i + strides[size_t(std::countr_zero(face))]));
      for (int e = 0; e < c; ++e)
        if (roots[e] == roots[c]) return false;
    }
    return true;
  };

  // Within a distance level, in rounds, as parallel thinning does: a round removes the cells that were removable
  // when it began (each checked again just before, so topology holds), and the cells they expose wait for the
  // next round. A level then peels one layer from every side at a time, instead of eating a sheet edge first,
  // row after row, before its middle has thinned to a curve.
  size_t visits = 0;
  std::vector<uint32_t> round, candidates;
  for (size_t r = 0; r < buckets.size(); ++r) {
    auto& bucket = buckets[r];
    while (!bucket.empty()) {
      ++rounds;
      round.swap(bucket);
      candidates.clear();
      for (const uint32_t i : round) {
        if ((++visits & 0xFFFF) == 0 && cancelled && cancelled()) throw Cancelled{};
        state[i] &= ~kQueued;
        if (state[i] == kEmpty && removable(i)) candidates.push_back(i);
      }
      round.clear();
      for (const uint32_t i : candidates) {
        if (state[i] != kEmpty || !removable(i)) continue;
        state[i] = kDeleted;
        for (uint32_t f = faces; f; f &= f - 1) {
          const size_t j = i + strides[size_t(std::countr_zero(f))];
          if (state[j] & kBackground) background.unite(i, uint32_t(j));
        }
        for (size_t k = 0; k < 26; ++k) {
          const size_t j = i + strides[k];
          if (state[j] != kEmpty) continue;
          state[j] |= kQueued;
          buckets[std::max(rank(j), r)].push_back(uint32_t(j));
        }
      }
    }
    std::vector<uint32_t>().swap(bucket);
  }
  return state;
}

}  // namespace

Graph Graph::from_edges(size_t nodes, std::span<const std::pair<uint32_t, uint32_t>> edges) {
  Graph g;
  g.offsets.assign(nodes + 1, 0);
  for (const auto& [a, b] : edges) ++g.offsets[a + 1], ++g.offsets[b + 1];
  for (size_t n = 0; n < nodes; ++n) g.offsets[n + 1] += g.offsets[n];
  g.adjacency.resize(edges.size() * 2);
  std::vector<uint32_t> fill(g.offsets.begin(), g.offsets.end() - 1);
  for (const auto& [a, b] : edges) g.adjacency[fill[a]++] = b, g.adjacency[fill[b]++] = a;
  return g;
}

Skeleton skeletonize(const VoxelGrid& grid, std::span<const uint32_t> d2, const CancelCheck& cancelled) {
  const GridShape& shape = grid.shape;
  Skeleton skeleton;
  skeleton.voxel_node.assign(shape.padded_count(), kNoNode);
  if (shape.empty()) return skeleton;
  const auto strides = shape.neighbour_strides();
  const auto& offsets = neighbour_offsets();
  std::vector<uint8_t> state = thin(grid, d2, cancelled);

  // Skeleton voxels, numbered through voxel_node for now.
  std::vector<uint32_t> cells;
  for (size_t i = 0; i < state.size(); ++i) {
    if (state[i] & kBackground) continue;
    skeleton.voxel_node[i] = uint32_t(cells.size());
    cells.push_back(uint32_t(i));
  }
  skeleton.voxels = cells.size();
  std::vector<uint8_t> alive(cells.size(), 1);
  std::vector<uint8_t> degree(cells.size(), 0);
  const auto for_neighbours = [&](uint32_t v, auto&& body) {
    for (size_t k = 0; k < 26; ++k) {
      const uint32_t w = skeleton.voxel_node[cells[v] + strides[k]];
      if (w != kNoNode && alive[w]) body(w, k);
    }
  };
  for (uint32_t v = 0; v < cells.size(); ++v) for_neighbours(v, [&](uint32_t, size_t) { ++degree[v]; });

  // A voxel with two neighbours that touch each other is a corner the graph can cut without changing its
  // connections; left in, it would close a triangle, a cycle the voxels do not have.
  const auto cut_corners = [&] {
    const auto voxel = [&](uint32_t v) { return shape.voxel_of_index(cells[v]); };
    std::vector<uint32_t> work;
    for (uint32_t v = 0; v < cells.size(); ++v)
      if (alive[v] && degree[v] == 2) work.push_back(v);
    while (!work.empty()) {
      const uint32_t v = work.back();
      work.pop_back();
      if (!alive[v] || degree[v] != 2) continue;
      uint32_t pair[2], found = 0;
      for_neighbours(v, [&](uint32_t w, size_t) { pair[found++] = w; });
      const glm::ivec3 d = glm::abs(voxel(pair[0]) - voxel(pair[1]));
      if (std::max({d.x, d.y, d.z}) > 1) continue;
      alive[v] = 0;
      for (uint32_t w : pair)
        if (--degree[w] == 2) work.push_back(w);
    }
  };
  cut_corners();

  // Prune side branches that end inside the maximal ball of their junction: they come from bumps of the
  // surface, not from the shape of the empty space.
  std::vector<uint32_t> ends;
  for (uint32_t v = 0; v < cells.size(); ++v)
    if (degree[v] == 1) ends.push_back(v);
  std::vector<uint32_t> branch;
  while (!ends.empty()) {
    const uint32_t end = ends.back();
    ends.pop_back();
    if (!alive[end] || degree[end] != 1) continue;
    branch.assign(1, end);
    uint32_t previous = kNoNode, current = end, junction = kNoNode;
    double length = 0.0;
    while (junction == kNoNode) {
      uint32_t next = kNoNode;
      size_t step = 0;
      for_neighbours(current, [&](uint32_t w, size_t k) {
        if (w != previous) next = w, step = k;
      });
      if (next == kNoNode) break;
      const glm::ivec3 o = offsets[step];
      length += std::sqrt(double(o.x * o.x + o.y * o.y + o.z * o.z));
      if (degree[next] >= 3)
        junction = next;
      else if (degree[next] == 2)
        previous = current, current = next, branch.push_back(next);
      else
        break;  // a lone curve: keep it
    }
    if (junction == kNoNode || length >= radius_in_voxels(d2[cells[junction]]) + 2.0) continue;
    for (uint32_t v : branch) {
      alive[v] = 0;
      for_neighbours(v, [&](uint32_t w, size_t) {
        if (--degree[w] == 1) ends.push_back(w);
      });
    }
    skeleton.pruned_voxels += branch.size();
  }

  cut_corners();

  // Nodes: each curve voxel, and each 26-connected group of junction voxels as one node.
  std::vector<uint32_t> node_of(cells.size(), kNoNode), representative;
  std::vector<uint32_t> stack;
  for (uint32_t v = 0; v < cells.size(); ++v) {
    if (!alive[v] || node_of[v] != kNoNode) continue;
    const uint32_t node = uint32_t(representative.size());
    representative.push_back(v);
    node_of[v] = node;
    if (degree[v] < 3) continue;
    stack.assign(1, v);
    while (!stack.empty()) {
      const uint32_t u = stack.back();
      stack.pop_back();
      if (d2[cells[u]] > d2[cells[representative[node]]]) representative[node] = u;
      for_neighbours(u, [&](uint32_t w, size_t) {
        if (degree[w] >= 3 && node_of[w] == kNoNode) node_of[w] = node, stack.push_back(w);
      });
    }
  }
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  for (uint32_t v = 0; v < cells.size(); ++v) {
    if (!alive[v]) continue;
    for_neighbours(v, [&](uint32_t w, size_t) {
      if (node_of[v] < node_of[w]) edges.emplace_back(node_of[v], node_of[w]);
    });
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  skeleton.graph = Graph::from_edges(representative.size(), edges);
  for (uint32_t r : representative) {
    skeleton.position.push_back(glm::vec3(shape.centre(shape.voxel_of_index(cells[r]))));
    skeleton.radius.push_back(float(radius_in_voxels(d2[cells[r]]) * shape.voxel_size));
  }

  // Nearest node through the empty space: Dial's Dijkstra with chamfer weights 3 (face), 4 (edge), 5 (corner).
  std::fill(skeleton.voxel_node.begin(), skeleton.voxel_node.end(), kNoNode);
  std::vector<uint32_t> distance(shape.padded_count(), UINT32_MAX);
  std::array<std::vector<uint32_t>, 6> ring;
  for (uint32_t v = 0; v < cells.size(); ++v) {
    if (!alive[v]) continue;
    distance[cells[v]] = 0;
    skeleton.voxel_node[cells[v]] = node_of[v];
    ring[0].push_back(cells[v]);
  }
  std::array<uint32_t, 26> weight{};
  for (size_t k = 0; k < 26; ++k) {
    const glm::ivec3 o = offsets[k];
    weight[k] = uint32_t(2 + std::abs(o.x) + std::abs(o.y) + std::abs(o.z));
  }
  size_t pending = 0;
  for (const auto& r : ring) pending += r.size();
  for (uint32_t d = 0; pending; ++d) {
    auto& bucket = ring[d % ring.size()];
    while (!bucket.empty()) {
      const uint32_t i = bucket.back();
      bucket.pop_back();
      --pending;
      if (distance[i] != d) continue;
      for (size_t k = 0; k < 26; ++k) {
        const size_t j = i + strides[k];
        const uint32_t dj = d + weight[k];
        if (grid.solid[j] || distance[j] <= dj) continue;
        distance[j] = dj;
        skeleton.voxel_node[j] = skeleton.voxel_node[i];
        ring[dj % ring.size()].push_back(uint32_t(j));
        ++pending;
      }
    }
  }
  return skeleton;
}

std::vector<uint32_t> graph_components(const Graph& graph, size_t* count) {
  std::vector<uint32_t> label(graph.node_count(), kNoNode), stack;
  uint32_t next = 0;
  for (uint32_t n = 0; n < graph.node_count(); ++n) {
    if (label[n] != kNoNode) continue;
    label[n] = next;
    stack.assign(1, n);
    while (!stack.empty()) {
      const uint32_t u = stack.back();
      stack.pop_back();
      for (uint32_t w : graph.neighbours(u))
        if (label[w] == kNoNode) label[w] = next, stack.push_back(w);
    }
    ++next;
  }
  if (count) *count = next;
  return label;
}

Betti graph_betti(const Graph& graph) {
  size_t components = 0;
  graph_components(graph, &components);
  return {components, graph.edge_count() + components - graph.node_count(), 0};
}

Betti empty_space_betti(const VoxelGrid& grid) {
  const GridShape& shape = grid.shape;
  if (shape.empty()) return {};
  const glm::ivec3 p = shape.padded();
  const auto empty = [&](int x, int y, int z) {
    if (x < 0 || y < 0 || z < 0 || x >= p.x || y >= p.y || z >= p.z) return false;
    return !grid.solid[(size_t(z) * size_t(p.y) + size_t(y)) * size_t(p.x) + size_t(x)];
  };
  // Euler characteristic of the union of closed cubes: lattice vertices, edges, faces and cubes it holds. A
  // lattice point (x, y, z) is the low corner of padded cell (x, y, z).
  long long chi = 0;
  for (int z = 0; z <= p.z; ++z)
    for (int y = 0; y <= p.y; ++y)
      for (int x = 0; x <= p.x; ++x) {
        bool cube = empty(x, y, z), vertex = false, edge[3] = {}, face[3] = {};
        for (int dz = -1; dz <= 0; ++dz)
          for (int dy = -1; dy <= 0; ++dy)
            for (int dx = -1; dx <= 0; ++dx) {
              if (!empty(x + dx, y + dy, z + dz)) continue;
              vertex = true;
              // Edge along axis a from this lattice point: its 4 cells have offset 0 along a.
              if (dx == 0) edge[0] = true;
              if (dy == 0) edge[1] = true;
              if (dz == 0) edge[2] = true;
              // Face normal to axis a: its 2 cells have offset 0 along both other axes.
              if (dy == 0 && dz == 0) face[0] = true;
              if (dx == 0 && dz == 0) face[1] = true;
              if (dx == 0 && dy == 0) face[2] = true;
            }
        chi += vertex - (edge[0] + edge[1] + edge[2]) + (face[0] + face[1] + face[2]) - cube;
      }
  // Components: the empty space 26-connected, the solid (padding included) 6-connected.
  CellSets empty_sets{std::vector<uint32_t>(shape.padded_count())};
  for (size_t i = 0; i < empty_sets.parent.size(); ++i) empty_sets.parent[i] = uint32_t(i);
  const auto strides = shape.neighbour_strides();
  for (size_t i = 0; i < grid.solid.size(); ++i) {
    if (grid.solid[i]) continue;
    for (size_t k = 0; k < 13; ++k)  // the 13 neighbours before this cell in raster order
      if (!grid.solid[i + strides[k]]) empty_sets.unite(uint32_t(i), uint32_t(i + strides[k]));
  }
  size_t b0 = 0;
  for (size_t i = 0; i < grid.solid.size(); ++i) b0 += !grid.solid[i] && empty_sets.find(uint32_t(i)) == i;
  CellSets solid = solid_components(grid);
  size_t solid_parts = 0;
  for (size_t i = 0; i < grid.solid.size(); ++i) solid_parts += grid.solid[i] && solid.find(uint32_t(i)) == i;
  Betti betti;
  betti.components = b0;
  betti.cavities = solid_parts - 1;
  betti.tunnels = size_t((long long)b0 + (long long)betti.cavities - chi);
  return betti;
}

}  // namespace bounce::topology
