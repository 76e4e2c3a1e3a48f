// The topology of the empty space: voxels, distance transform, skeleton, segmentation, clusters and gates.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <random>
#include <set>
#include <utility>

#include <glm/geometric.hpp>

#include "embree/embree_device.h"
#include "topology/distance_transform.h"
#include "topology/local_topology.h"
#include "topology/shared_glsl.h"
#include "topology/topology.h"
#include "topology/voxelize.h"
#include "topology_scenes.h"

namespace bounce::topology {
namespace {

using test::Soup;

Topology build_at(const Soup& soup, int resolution) {
  Settings settings;
  settings.resolution = resolution;
  return build(soup.vertices, settings);
}

// Nodes, segmented nodes and clusters of the skeleton component holding point p.
struct Component {
  uint32_t label = kNoNode;
  std::vector<uint32_t> label_of;  // per original node
  size_t clusters = 0;
  size_t nodes = 0;
  std::vector<uint8_t> has_cluster;  // per cluster
  std::vector<Gate> gates;           // between clusters of the component
};
Component component_at(const Topology& t, glm::vec3 p) {
  Component c;
  c.label_of = graph_components(t.skeleton.graph);
  const uint32_t node = t.node_at(p, glm::vec3(0.0f));
  if (node == kNoNode) return c;
  c.label = c.label_of[node];
  c.has_cluster.assign(t.cluster_count, 0);
  for (uint32_t s = 0; s < t.segmented.original.size(); ++s) {
    if (c.label_of[t.segmented.original[s]] != c.label) continue;
    ++c.nodes;
    if (!c.has_cluster[t.cluster_of[s]]) c.has_cluster[t.cluster_of[s]] = 1, ++c.clusters;
  }
  for (const Gate& gate : t.gates)
    if (c.has_cluster[gate.clusters[0]]) c.gates.push_back(gate);
  return c;
}

void expect_skeleton_keeps_topology(const Topology& t) {
  const Betti space = empty_space_betti(t.grid);
  const Betti graph = graph_betti(t.skeleton.graph);
  EXPECT_EQ(graph.components, space.components);
  EXPECT_EQ(graph.tunnels, space.tunnels);
  const Betti segmented = graph_betti(t.segmented.graph);
  EXPECT_EQ(segmented.components, space.components);
  EXPECT_EQ(segmented.tunnels, space.tunnels);
}

TEST(TopologyDistance, ExactAgainstBruteForceOnRandomGrids) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 6; ++trial) {
    VoxelGrid grid;
    grid.shape.dims = {int(5 + rng() % 14), int(5 + rng() % 14), int(5 + rng() % 14)};
    grid.solid.assign(grid.shape.padded_count(), 1);
    const float density = 0.02f + 0.1f * float(trial);
    std::vector<glm::ivec3> solid;
    for (size_t i = 0; i < grid.solid.size(); ++i) {
      const glm::ivec3 v = grid.shape.voxel_of_index(i);
      if (grid.shape.inside(v)) grid.solid[i] = std::uniform_real_distribution<float>()(rng) < density;
      if (grid.solid[i]) solid.push_back(v);
    }
    const std::vector<uint32_t> d2 = squared_distance_transform(grid);
    for (size_t i = 0; i < grid.solid.size(); ++i) {
      const glm::ivec3 v = grid.shape.voxel_of_index(i);
      uint32_t best = UINT32_MAX;
      for (const glm::ivec3& s : solid) {
        const glm::ivec3 d = s - v;
        best = std::min(best, uint32_t(d.x * d.x + d.y * d.y + d.z * d.z));
      }
      ASSERT_EQ(d2[i], best) << "trial " << trial << " voxel " << v.x << "," << v.y << "," << v.z;
    }
  }
}

TEST(TopologyLocal, SimpleAndIsthmusPoints) {
  const auto& o = neighbour_offsets();
  const auto mask = [&](auto&& in) {
    uint32_t m = 0;
    for (int k = 0; k < 26; ++k)
      if (in(o[size_t(k)])) m |= 1u << k;
    return m;
  };
  // Half space below: simple.
  EXPECT_TRUE(classify_neighbourhood(mask([](glm::ivec3 d) { return d.z <= 0; })).simple());
  // A line along x: an isthmus, not simple.
  const LocalTopology line = classify_neighbourhood(mask([](glm::ivec3 d) { return d.y == 0 && d.z == 0; }));
  EXPECT_TRUE(line.isthmus());
  EXPECT_FALSE(line.simple());
  // The end of a line: simple.
  EXPECT_TRUE(classify_neighbourhood(mask([](glm::ivec3 d) { return d == glm::ivec3(1, 0, 0); })).simple());
  // A plane: one object component, two background components.
  const LocalTopology plane = classify_neighbourhood(mask([](glm::ivec3 d) { return d.z == 0; }));
  EXPECT_EQ(plane.object_components, 1);
  EXPECT_EQ(plane.background_components, 2);
  // Inside: no background neighbour at all, not simple.
  EXPECT_FALSE(classify_neighbourhood((1u << 26) - 1).simple());
}

TEST(TopologyVoxelize, ThinDiagonalWallDoesNotLeak) {
  // A wall at 45 degrees through the whole grid splits the empty space in two, however thin.
  Soup s;
  s.vertices = {{0, 0, 0}, {10, 10, 0}, {10, 10, 10}, {0, 0, 0}, {10, 10, 10}, {0, 0, 10}};
  s.box({0, 0, 0}, {10, 10, 10});
  const VoxelGrid grid = voxelize(s.vertices, fit_grid(s.vertices, 37, 2));
  EXPECT_EQ(empty_space_betti(grid).components, 3u);  // two halves inside, the outside
}

TEST(TopologyScenes, ClosedBoxIsOneClusterWithoutGates) {
  const Topology t = build_at(test::closed_box(), 64);
  expect_skeleton_keeps_topology(t);
  const Component inside = component_at(t, {5, 3, 2});
  ASSERT_NE(inside.label, kNoNode);
  EXPECT_EQ(inside.clusters, 1u);
  EXPECT_TRUE(inside.gates.empty()) << t.summary();
}

// A voxel takes its nearest skeleton node's cluster, so the voxels of two clusters may touch where no skeleton edge
// joins them: in the open box, branches of the skeleton into the space around it and into the room's edges claim
// slabs of the room. Light crossing such a boundary needs a gate there as much as through a doorway.
TEST(TopologyScenes, ClustersWhoseVoxelsTouchHaveAGate) {
  const Topology t = build_at(test::open_box(), 128);
  std::set<std::pair<uint32_t, uint32_t>> gated;
  for (const Gate& gate : t.gates) gated.insert(std::minmax(gate.clusters[0], gate.clusters[1]));
  const GridShape& shape = t.grid.shape;
  const glm::ivec3 padded = shape.padded();
  const std::size_t strides[3] = {1, std::size_t(padded.x), std::size_t(padded.x) * std::size_t(padded.y)};
  std::set<std::pair<uint32_t, uint32_t>> touching;
  for (std::size_t i = 0; i < t.skeleton.voxel_node.size(); ++i)
    for (std::size_t stride : strides) {
      if (i + stride >= t.skeleton.voxel_node.size()) continue;
      const uint32_t a = t.cluster_of_node(t.skeleton.voxel_node[i]);
      const uint32_t b = t.cluster_of_node(t.skeleton.voxel_node[i + stride]);
      if (a != kNoNode && b != kNoNode && a != b) touching.insert(std::minmax(a, b));
    }
  EXPECT_GE(touching.size(), 1u) << t.summary();
  for (const auto& pair : touching) EXPECT_TRUE(gated.count(pair)) << pair.first << "-" << pair.second;
}

// Two clusters a skeleton edge joins may touch beyond that edge's opening: one room's cluster claims a dome of the
// next room's voxels around their doorway, and Sponza's galleries meet the court through a row of arches (the
// Topology method lost half the light crossing between clusters in Sponza's court, 0.864 of shadow rays' light
// in the middle third of its view). Light crossing anywhere on their boundary needs a gate over it
// (add_boundary_gates): every face between their voxels lies over one of their gates' rectangles.
TEST(TopologyScenes, BoundariesOfJoinedClustersLieUnderTheirGates) {
  for (const auto& [soup, resolution] :
       {std::pair{test::two_rooms(), 128}, std::pair{test::two_rooms(), 192}, std::pair{test::open_box(), 128}}) {
    const Topology t = build_at(soup, resolution);
    std::set<std::pair<uint32_t, uint32_t>> joined;
    for (const Gate& gate : t.gates)
      if (gate.kind == Gate::Kind::kSkeleton) joined.insert(std::minmax(gate.clusters[0], gate.clusters[1]));
    const GridShape& shape = t.grid.shape;
    const glm::ivec3 padded = shape.padded();
    const std::size_t strides[3] = {1, std::size_t(padded.x), std::size_t(padded.x) * std::size_t(padded.y)};
    const auto over = [&](const Gate& gate, glm::vec3 face) {
      const glm::vec3 offset = face - gate.centre;
      return std::abs(glm::dot(offset, gate.axis_u)) <= gate.half_u &&
             std::abs(glm::dot(offset, glm::cross(gate.normal, gate.axis_u))) <= gate.half_v;
    };
    std::size_t faces = 0, outside = 0, outside_skeleton_gates = 0;
    for (std::size_t i = 0; i < t.skeleton.voxel_node.size(); ++i)
      for (std::size_t stride : strides) {
        if (i + stride >= t.skeleton.voxel_node.size()) continue;
        const uint32_t a = t.cluster_of_node(t.skeleton.voxel_node[i]);
        const uint32_t b = t.cluster_of_node(t.skeleton.voxel_node[i + stride]);
        if (a == kNoNode || b == kNoNode || a == b || !joined.count(std::minmax(a, b))) continue;
        const glm::vec3 face(0.5 *
                             (shape.centre(shape.voxel_of_index(i)) + shape.centre(shape.voxel_of_index(i + stride))));
        const auto outside_of = [&](bool skeleton_only) {
          return std::none_of(t.gates.begin(), t.gates.end(), [&](const Gate& gate) {
            return (!skeleton_only || gate.kind == Gate::Kind::kSkeleton) &&
                   std::minmax(gate.clusters[0], gate.clusters[1]) == std::minmax(a, b) && over(gate, face);
          });
        };
        ++faces;
        outside += outside_of(false);
        outside_skeleton_gates += outside_of(true);
      }
    std::printf(
        "%d voxels: of %zu faces between joined clusters, %zu lie outside their gates (%zu outside the "
        "skeleton's gates alone)\n",
        resolution, faces, outside, outside_skeleton_gates);
    EXPECT_GT(faces, 0u);
    EXPECT_LE(double(outside), 0.01 * double(faces)) << resolution;
  }
}

class TopologyTwoRooms : public testing::TestWithParam<int> {};

TEST_P(TopologyTwoRooms, AreTwoClustersWithAGateInTheDoorway) {
  const Topology t = build_at(test::two_rooms(), GetParam());
  expect_skeleton_keeps_topology(t);
  const Component inside = component_at(t, {5, 5, 2});
  ASSERT_NE(inside.label, kNoNode);
  EXPECT_EQ(inside.clusters, 2u) << t.summary();
  EXPECT_NE(t.cluster_at({5, 5, 2}, {}), t.cluster_at({15, 5, 2}, {}));
  // One gate in the doorway; the rest of the boundary between the rooms' voxels (a room's cluster claims voxels
  // of the other around the doorway) only with a ray's word.
  std::vector<Gate> trusted;
  std::copy_if(inside.gates.begin(), inside.gates.end(), std::back_inserter(trusted),
               [](const Gate& g) { return !g.needs_ray(); });
  ASSERT_EQ(trusted.size(), 1u) << t.summary();
  const Gate& gate = trusted[0];
  const float h = float(t.grid.shape.voxel_size);
  // Its centre within the opening (the wall is two voxels thick).
  EXPECT_NEAR(gate.centre.x, test::kDoorLo.x, 2.0f * h);
  EXPECT_GT(gate.centre.y, test::kDoorLo.y);
  EXPECT_LT(gate.centre.y, test::kDoorHi.y);
  EXPECT_GT(gate.centre.z, test::kDoorLo.z);
  EXPECT_LT(gate.centre.z, test::kDoorHi.z);
  // The gate is the rectangle around the opening: its half extents those of the doorway (2 m wide, 3 m high) to
  // within the voxels' steps, not the empty voxels' (half a voxel short on each side, on average, where the
  // conservative voxelization marks the voxels the jambs pass through solid).
  const float small = std::min(gate.half_u, gate.half_v), large = std::max(gate.half_u, gate.half_v);
  const float half_width = 0.5f * (test::kDoorHi.y - test::kDoorLo.y), half_height = 0.5f * test::kDoorHi.z;
  EXPECT_NEAR(small, half_width, 0.6f * h);
  EXPECT_NEAR(large, half_height, 0.6f * h);
  EXPECT_GT(std::abs(gate.normal.x), 0.85f);  // across the wall, within the tilt of voxel steps
  // The gate is the boundary: surfaces along the middle wall take their own room's cluster (the skeleton nodes
  // past the doorway's neck once gave a slab of room B room A's cluster). Within about three voxels of the wall
  // a point's nearest node through the empty space may still be one past the neck.
  const uint32_t room_a = t.cluster_at({5, 5, 2}, {}), room_b = t.cluster_at({15, 5, 2}, {});
  for (float d : {4.0f * h, 0.6f, 1.0f, 2.0f}) {
    if (d < 4.0f * h) continue;
    for (const auto& [point, normal] :
         {std::pair{glm::vec3(0, 0, 2), glm::vec3(0, 1, 0)}, std::pair{glm::vec3(0, 10, 2), glm::vec3(0, -1, 0)},
          std::pair{glm::vec3(0, 2, 0), glm::vec3(0, 0, 1)}, std::pair{glm::vec3(0, 8, 4), glm::vec3(0, 0, -1)}}) {
      EXPECT_EQ(t.cluster_at(point + glm::vec3(10.0f - d, 0, 0), normal, Topology::Side::Front), room_a) << d;
      EXPECT_EQ(t.cluster_at(point + glm::vec3(10.0f + d, 0, 0), normal, Topology::Side::Front), room_b) << d;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Resolutions, TopologyTwoRooms, testing::Values(64, 96, 128, 192, 256));

TEST(TopologyScenes, RingCorridorHasExactlyOneCycle) {
  const Topology t = build_at(test::ring_corridor(), 96);
  expect_skeleton_keeps_topology(t);
  EXPECT_EQ(empty_space_betti(t.grid).tunnels, 1u);
  EXPECT_EQ(graph_betti(t.skeleton.graph).tunnels, 1u) << t.summary();
}

TEST(TopologyScenes, UCorridorHasCurvatureNodesAtTheBendsAndNoEdgeThroughAWall) {
  const test::Soup soup = test::u_corridor();
  const Topology t = build_at(soup, 96);
  expect_skeleton_keeps_topology(t);
  const Component corridor = component_at(t, {1, 5, 1.5f});
  ASSERT_NE(corridor.label, kNoNode);
  // Both bends hold a kept node that is not a line end's topology node.
  for (glm::vec3 bend : {glm::vec3(1, 9, 1.5f), glm::vec3(11, 9, 1.5f)}) {
    float nearest = 1e9f;
    for (uint32_t s = 0; s < t.segmented.original.size(); ++s) {
      const uint32_t o = t.segmented.original[s];
      if (corridor.label_of[o] != corridor.label) continue;
      if (t.segmented.kind[o] == NodeKind::Curvature)
        nearest = std::min(nearest, glm::distance(t.skeleton.position[o], bend));
    }
    EXPECT_LT(nearest, 2.0f) << "no curvature node near the bend at " << bend.x << "," << bend.y << "\n" << t.summary();
  }
  embree::Scene scene;
  scene.add_triangles(soup.vertices);
  scene.commit();
  for (uint32_t a = 0; a < t.segmented.graph.node_count(); ++a) {
    for (uint32_t b : t.segmented.graph.neighbours(a)) {
      const glm::vec3 pa = t.skeleton.position[t.segmented.original[a]];
      const glm::vec3 pb = t.skeleton.position[t.segmented.original[b]];
      EXPECT_FALSE(scene.occluded(pa, pb - pa, 0.0f, 1.0f)) << "segmented edge " << a << "-" << b << " crosses a wall";
    }
  }
}

TEST(TopologyScenes, RandomBlocksKeepComponentsAndTunnels) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 4; ++trial) {
    Soup s;
    s.box({0, 0, 0}, {10, 10, 10});
    std::uniform_real_distribution<float> u(0.5f, 9.5f);
    for (int b = 0; b < 6; ++b) {
      const glm::vec3 a(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
      s.box(glm::min(a, c), glm::max(a, c));
    }
    const Topology t = build_at(s, 48);
    SCOPED_TRACE(trial);
    expect_skeleton_keeps_topology(t);
  }
}

}  // namespace
}  // namespace bounce::topology

namespace bounce::topology {
namespace {

// Hard inputs: no crash, no NaN, and the lookups stay in range.
void expect_sane(const Topology& t) {
  for (size_t n = 0; n < t.skeleton.position.size(); ++n) {
    ASSERT_TRUE(std::isfinite(t.skeleton.position[n].x + t.skeleton.position[n].y + t.skeleton.position[n].z));
    ASSERT_TRUE(std::isfinite(t.skeleton.radius[n]) && t.skeleton.radius[n] > 0.0f);
  }
  for (const Gate& g : t.gates) {
    ASSERT_TRUE(std::isfinite(g.centre.x + g.centre.y + g.centre.z + g.normal.x + g.normal.y + g.normal.z));
    ASSERT_LT(g.clusters[0], t.cluster_count);
    ASSERT_LT(g.clusters[1], t.cluster_count);
  }
  for (uint32_t c : t.cluster_of) ASSERT_LT(c, t.cluster_count);
  for (uint32_t node : t.skeleton.voxel_node) ASSERT_TRUE(node == kNoNode || node < t.skeleton.position.size());
  expect_skeleton_keeps_topology(t);
}

TEST(TopologyHardInputs, EmptySceneGivesAnEmptyTopology) {
  const Topology t = build_at(Soup(), 64);
  EXPECT_TRUE(t.grid.shape.empty());
  EXPECT_EQ(t.cluster_count, 0u);
  EXPECT_EQ(t.node_at({0, 0, 0}, {0, 0, 1}), kNoNode);
}

TEST(TopologyHardInputs, NonFiniteTrianglesAreSkipped) {
  Soup s = test::closed_box();
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  s.vertices.insert(s.vertices.end(), {{nan, 0, 0}, {1, 1, 1}, {2, 0, 0}, {inf, 0, 0}, {0, 1e30f, 0}, {0, 0, 1}});
  const Topology t = build_at(s, 48);
  expect_sane(t);
  EXPECT_EQ(component_at(t, {5, 3, 2}).clusters, 1u);
  EXPECT_EQ(t.node_at({nan, 0, 0}, {0, 0, 1}), kNoNode);
}

TEST(TopologyHardInputs, SolidGridHasNoEmptySpace) {
  // Planes closer than a voxel everywhere, no margin: every voxel is solid.
  Soup s;
  for (int i = 0; i <= 40; ++i) s.quad({0, 0, i * 0.25f}, {10, 10, i * 0.25f}, 2);
  Settings settings;
  settings.resolution = 32;
  settings.margin = 0;
  const Topology t = build(s.vertices, settings);
  EXPECT_EQ(t.grid.empty_count(), 0u);
  EXPECT_EQ(t.skeleton.graph.node_count(), 0u);
  EXPECT_EQ(t.cluster_count, 0u);
  EXPECT_EQ(t.node_at({5, 5, 5}, {0, 0, 1}), kNoNode);
}

TEST(TopologyHardInputs, SingleTriangleAndDegenerateOnes) {
  Soup s;
  s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  expect_sane(build_at(s, 64));
  s.vertices = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {3, 3, 3}, {3, 3, 3}};  // a segment, a point
  expect_sane(build_at(s, 32));
}

TEST(TopologyHardInputs, ScaleDoesNotMatter) {
  for (float scale : {1e-4f, 1e4f}) {
    Soup s = test::two_rooms();
    for (glm::vec3& v : s.vertices) v *= scale;
    const Topology t = build_at(s, 96);
    SCOPED_TRACE(scale);
    expect_sane(t);
    const Component inside = component_at(t, glm::vec3(5, 5, 2) * scale);
    EXPECT_EQ(inside.clusters, 2u);
    EXPECT_EQ(inside.gates.size(), 1u);
  }
}

TEST(TopologyHardInputs, ResolutionOne) {
  const Topology one = build_at(test::closed_box(), 1);
  EXPECT_EQ(one.grid.shape.dims, glm::ivec3(1));
  expect_sane(one);
}

// The largest resolution over a scene that is mostly empty space: the most voxels to thin.
TEST(TopologyHardInputs, LargestResolution) {
  Soup tetra;
  tetra.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {0, 0, 1}, {1, 1, 1}};
  const Topology largest = build_at(tetra, kMaxResolution + 100);
  EXPECT_EQ(std::max({largest.grid.shape.dims.x, largest.grid.shape.dims.y, largest.grid.shape.dims.z}),
            kMaxResolution);
  expect_sane(largest);
  std::printf("%s", largest.summary().c_str());
}

TEST(TopologyBuild, CancelStopsTheBuild) {
  int calls = 0;
  EXPECT_THROW(build(test::two_rooms().vertices, Settings{},
                     [&](BuildStage stage, float) { return ++calls < 3 && stage != BuildStage::Thinning; }),
               Cancelled);
}

TEST(TopologyBuild, SameInputSameTopology) {
  const Topology a = build_at(test::two_rooms(), 64), b = build_at(test::two_rooms(), 64);
  EXPECT_EQ(a.skeleton.position, b.skeleton.position);
  EXPECT_EQ(a.cluster_of, b.cluster_of);
  EXPECT_EQ(a.skeleton.voxel_node, b.skeleton.voxel_node);
}

// Fitted to the surfaces (fit_gates_to_surfaces), the gate between the window room and the outside is the window:
// in the wall's plane, its rectangle the window's to within the probes' step (a quarter voxel). From the voxels
// alone it stood a voxel layer into the room (y = 0.32 at 128^3), and at 64^3 it was 1.33 m wide for a 2 m
// window. At 64^3 the window, 1.2 m high, is less than two voxels (0.67 m) across: its gate is left out, and the
// room and the outside are not joined (shadow rays or passages decide).
TEST(TopologyGates, FittedToTheSurfacesAroundAWindow) {
  const Soup soup = test::room_with_window();
  embree::Scene scene;
  scene.add_triangles(soup.vertices);
  scene.commit();
  const RayQueries rays{{}, [&scene](glm::vec3 origin, glm::vec3 direction) {
                          const auto hit =
                              scene.intersect(origin, direction, 0.0f, std::numeric_limits<float>::infinity());
                          return hit ? Occluders::Hit{hit->t, glm::vec3(0.0f)} : Occluders::Hit{};
                        }};
  for (const int resolution : {64, 128, 256}) {
    Settings settings;
    settings.resolution = resolution;
    const Topology t = build(soup.vertices, settings, {}, rays);
    const uint32_t inside = t.cluster_at({3, 2, 1.5f}, {}), outside = t.cluster_at({3, -2, 1.5f}, {});
    ASSERT_NE(inside, outside) << t.summary();
    const auto window = std::find_if(t.gates.begin(), t.gates.end(), [&](const Gate& g) {
      return std::minmax(g.clusters[0], g.clusters[1]) == std::minmax(inside, outside);
    });
    if (resolution == 64) {
      EXPECT_EQ(window, t.gates.end());
      EXPECT_FALSE(t.joined(inside, outside));
      continue;
    }
    ASSERT_NE(window, t.gates.end()) << t.summary();
    EXPECT_FALSE(window->needs_ray());
    const float step = 0.25f * float(t.grid.shape.voxel_size);
    const glm::vec3 centre = 0.5f * (test::kWindowLo + test::kWindowHi);
    EXPECT_NEAR(window->centre.x, centre.x, step) << resolution;
    EXPECT_NEAR(window->centre.y, centre.y, step) << resolution;
    EXPECT_NEAR(window->centre.z, centre.z, step) << resolution;
    const bool u_across = std::abs(window->axis_u.x) > 0.9f;
    const float half_width = u_across ? window->half_u : window->half_v;
    const float half_height = u_across ? window->half_v : window->half_u;
    EXPECT_NEAR(half_width, 0.5f * (test::kWindowHi.x - test::kWindowLo.x), step) << resolution;
    EXPECT_NEAR(half_height, 0.5f * (test::kWindowHi.z - test::kWindowLo.z), step) << resolution;
  }
}

// The passages of the sunlit interior in small (room_with_deep_blinds), whose slats' gaps the grid closes. Light
// crosses its window unevenly, and a rectangle centred on the crossings' weighted mean reached past the window on
// the other side by as much: in the budget's sunlit interior 2.66 x 1.88 m for a 2 x 1.3 m window, 0.5 m below the
// sill, and light through that overhang passed the wall. Each passage's rectangle stays within the window, but for
// the fit's margin of half a voxel and the tilt of its plane.
// The topology of `soup` at the default settings, its passages and occluders estimated by Embree.
Topology build_with_embree(const Soup& soup) {
  embree::Scene scene;
  scene.add_triangles(soup.vertices);
  scene.commit();
  const RayQueries rays{[&scene](glm::vec3 from, glm::vec3 to) {
                          const float distance = glm::length(to - from);
                          return !(distance > 0.0f) || !scene.occluded(from, (to - from) / distance, 0.0f, distance);
                        },
                        [&scene](glm::vec3 origin, glm::vec3 direction) {
                          const auto hit =
                              scene.intersect(origin, direction, 0.0f, std::numeric_limits<float>::infinity());
                          return hit ? Occluders::Hit{hit->t, hit->normal} : Occluders::Hit{};
                        }};
  return build(soup.vertices, Settings{}, {}, rays);
}

TEST(TopologyPassages, RectanglesStayWithinTheirOpening) {
  const Topology t = build_with_embree(test::room_with_deep_blinds());
  ASSERT_GT(t.passages.count(), 0u) << t.summary();
  const float margin = float(t.grid.shape.voxel_size);
  for (const Passage& passage : t.passages.passages) {
    const Gate& g = passage.gate;
    const glm::vec3 v = glm::cross(g.normal, g.axis_u);
    for (const float su : {-1.0f, 1.0f})
      for (const float sv : {-1.0f, 1.0f}) {
        const glm::vec3 corner = g.centre + su * g.half_u * g.axis_u + sv * g.half_v * v;
        EXPECT_GE(corner.x, test::kDeepWindowLo.x - margin) << g.clusters[0] << "-" << g.clusters[1];
        EXPECT_LE(corner.x, test::kDeepWindowHi.x + margin) << g.clusters[0] << "-" << g.clusters[1];
        EXPECT_GE(corner.z, test::kDeepWindowLo.z - margin) << g.clusters[0] << "-" << g.clusters[1];
        EXPECT_LE(corner.z, test::kDeepWindowHi.z + margin) << g.clusters[0] << "-" << g.clusters[1];
      }
  }
}

// The deep blinds' room is empty: its ceiling sees all of its floor, and no occluder should hide a light on the floor
// from a receiver on the ceiling. Beside the window, a bin's nearer ray met the sill's top in the window's depth
// and stood for the bin, and its other ray, which met the floor, counted toward its share while it lay within 1.25
// times the sill's distance: the sill's plane then held the whole floor below it. Of the floor's light (lights in
// front of the window, weighed by 1 / d^2) the ceiling kept 0.980, and 1.8 % of the pairs were hidden whole; with
// the share of the rays that meet a surface not behind the plane, 0.987 and 0.32 % (two rays per bin: where one
// meets the sill, half the bin).
TEST(TopologyOccluders, AnEmptyRoomsCeilingSeesItsFloor) {
  const Topology t = build_with_embree(test::room_with_deep_blinds());
  const float voxel = float(t.grid.shape.voxel_size);
  double kept = 0.0, all = 0.0;
  int pairs = 0, hidden_whole = 0;
  for (int iy = 0; iy < 45; ++iy)
    for (int ix = 0; ix < 56; ++ix) {
      const glm::vec3 x(0.2f + 0.1f * float(ix), 0.3f + 0.1f * float(iy), 2.8f - 1e-3f);
      const auto hits = cell_hits(t.occluders, t.grid.shape, x);
      for (int ly = 0; ly < 11; ++ly)
        for (int lx = 0; lx < 10; ++lx) {
          const glm::vec3 offset = glm::vec3(1.6f + 0.2f * float(lx), 0.3f + 0.2f * float(ly), 1e-3f) - x;
          const float share = unoccluded(hits, offset, TOPOLOGY_WITHIN_CLUSTER, voxel);
          kept += share / glm::dot(offset, offset);
          all += 1.0 / glm::dot(offset, offset);
          ++pairs;
          hidden_whole += share == 0.0f ? 1 : 0;
        }
    }
  std::printf("the ceiling keeps %.4f of the floor's light; %d of %d pairs hidden whole\n", kept / all, hidden_whole,
              pairs);
  EXPECT_GT(kept / all, 0.984);
  EXPECT_LT(double(hidden_whole), 0.005 * double(pairs));
}

}  // namespace
}  // namespace bounce::topology
