// Screen-Space VPL Propagation: the sample sets, the paraboloid map and k-means against their definitions, and
// the GPU pass against the sphere furnace's closed forms and the hard cases of the issue.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "passes/gbuffer/gbuffer_pass.h"
#include "passes/light_views.h"
#include "passes/ssvp/ssvp_math.h"
#include "render_fixture.h"
#include "topology_scenes.h"

namespace bounce::test {
namespace {

using ssvp::ClusterPoint;

TEST(SsvpMath, VanDerCorputMirrorsTheBits) {
  EXPECT_EQ(ssvp::ssvp_van_der_corput(0), 0.0f);
  EXPECT_EQ(ssvp::ssvp_van_der_corput(1), 0.5f);
  EXPECT_EQ(ssvp::ssvp_van_der_corput(2), 0.25f);
  EXPECT_EQ(ssvp::ssvp_van_der_corput(3), 0.75f);
  EXPECT_EQ(ssvp::ssvp_van_der_corput(5), 0.625f);  // 101 -> 0.101
  EXPECT_EQ(ssvp::ssvp_van_der_corput(6), 0.375f);  // 110 -> 0.011
}

TEST(SsvpMath, HammersleySetIsStratifiedInBothAxes) {
  // Eq. 1 with n = 2^m: every elementary interval of area 1/n holds exactly one point (a (0, m, 2)-net).
  const uint32_t n = 256;
  const auto set = ssvp::hammersley_set(n, glm::vec2(0.0f));
  for (uint32_t k = 0; k < n; ++k) EXPECT_FLOAT_EQ(set[k].x, float(k) / float(n));
  for (int bits_x = 0; bits_x <= 8; ++bits_x) {
    const int nx = 1 << bits_x, ny = int(n) / nx;
    std::vector<int> count(n, 0);
    for (const glm::vec2& p : set) ++count[std::size_t(int(p.x * nx) * ny + int(p.y * ny))];
    for (int c : count) EXPECT_EQ(c, 1) << nx << " x " << ny;
  }
  // A rotated set stays in [0, 1)^2.
  for (const glm::vec2& p : ssvp::hammersley_set(n, glm::vec2(0.731f, 0.377f))) {
    EXPECT_GE(p.x, 0.0f);
    EXPECT_LT(p.x, 1.0f);
    EXPECT_GE(p.y, 0.0f);
    EXPECT_LT(p.y, 1.0f);
  }
}

TEST(SsvpMath, ParaboloidMapRoundTrips) {
  for (float theta = 0.0f; theta <= 0.5f * kPi; theta += 0.05f)
    for (float phi = 0.0f; phi < 2.0f * kPi; phi += 0.3f) {
      const glm::vec3 d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      const glm::vec2 p = ssvp::ssvp_paraboloid_point(d);
      EXPECT_LE(glm::length(p), 1.0f + 1e-6f);
      const glm::vec3 back = ssvp::ssvp_paraboloid_direction(p);
      EXPECT_NEAR(glm::length(back - d), 0.0f, 1e-5f) << theta << " " << phi;
    }
  // The horizon maps onto the unit circle, the normal onto the centre.
  EXPECT_NEAR(glm::length(ssvp::ssvp_paraboloid_point(glm::vec3(1, 0, 0))), 1.0f, 1e-6f);
  EXPECT_EQ(ssvp::ssvp_paraboloid_point(glm::vec3(0, 0, 1)), glm::vec2(0.0f));
}

TEST(SsvpMath, ParaboloidJacobianIntegratesToTheHemisphere) {
  // Midpoint rule over the disk in polar coordinates: the solid angle density integrates to 2 pi, and the
  // cosine-weighted density to pi.
  double solid_angle = 0.0, projected = 0.0;
  const int rings = 2000;
  for (int i = 0; i < rings; ++i) {
    const float r = (i + 0.5f) / rings;
    const glm::vec2 p(r, 0.0f);
    const double ring_area = 2.0 * kPi * r / rings;
    solid_angle += ssvp::ssvp_paraboloid_solid_angle_density(p) * ring_area;
    projected += ssvp::ssvp_paraboloid_solid_angle_density(p) * ssvp::ssvp_paraboloid_direction(p).z * ring_area;
  }
  EXPECT_NEAR(solid_angle, 2.0 * kPi, 1e-4);
  EXPECT_NEAR(projected, kPi, 1e-4);
  // Finite differences of the map agree with the closed form.
  for (glm::vec2 p : {glm::vec2(0.1f, 0.2f), glm::vec2(0.7f, -0.3f), glm::vec2(-0.2f, 0.9f)}) {
    const float h = 1e-3f;
    const glm::vec3 dx =
        (ssvp::ssvp_paraboloid_direction(p + glm::vec2(h, 0)) - ssvp::ssvp_paraboloid_direction(p - glm::vec2(h, 0))) /
        (2 * h);
    const glm::vec3 dy =
        (ssvp::ssvp_paraboloid_direction(p + glm::vec2(0, h)) - ssvp::ssvp_paraboloid_direction(p - glm::vec2(0, h))) /
        (2 * h);
    EXPECT_NEAR(glm::length(glm::cross(dx, dy)), ssvp::ssvp_paraboloid_solid_angle_density(p), 2e-3f);
  }
}

TEST(SsvpMath, DiskSamplesAreUniform) {
  const uint32_t n = 4096;
  const auto disk = ssvp::disk_set(n, glm::vec2(0.0f));
  // Equal-area rings and sectors hold equal shares (chi-square far below its 99.9 % point for 63 dof, 103).
  const int rings = 8, sectors = 8;
  std::vector<int> count(rings * sectors, 0);
  for (const glm::vec2& p : disk) {
    const float r2 = glm::dot(p, p);
    ASSERT_LE(r2, 1.0f + 1e-5f);
    const int ring = std::min(int(r2 * rings), rings - 1);
    const float angle = std::atan2(p.y, p.x) + kPi;
    const int sector = std::min(int(angle / (2 * kPi) * sectors), sectors - 1);
    ++count[ring * sectors + sector];
  }
  const double expected = double(n) / (rings * sectors);
  double chi2 = 0.0;
  for (int c : count) chi2 += (c - expected) * (c - expected) / expected;
  EXPECT_LT(chi2, 103.0);
  // Mean radius^2 of a uniform disk is 1/2.
  double mean_r2 = 0.0;
  for (const glm::vec2& p : disk) mean_r2 += glm::dot(p, p) / n;
  EXPECT_NEAR(mean_r2, 0.5, 0.01);
}

TEST(SsvpMath, ClusterMetricPenalisesDissimilarNormals) {
  const glm::vec3 up(0, 0, 1), side(1, 0, 0);
  const float same = ssvp::ssvp_cluster_distance(glm::vec3(0), up, glm::vec3(0), up, 0.6f, 0.4f, 1.0f);
  const float turned = ssvp::ssvp_cluster_distance(glm::vec3(0), side, glm::vec3(0), up, 0.6f, 0.4f, 1.0f);
  const float opposite = ssvp::ssvp_cluster_distance(glm::vec3(0), -up, glm::vec3(0), up, 0.6f, 0.4f, 1.0f);
  EXPECT_EQ(same, 0.0f);
  EXPECT_FLOAT_EQ(turned, 0.2f);
  EXPECT_FLOAT_EQ(opposite, 0.4f);
  // Scale-free: scaling the scene and the length scale together changes nothing.
  const float near = ssvp::ssvp_cluster_distance(glm::vec3(1, 2, 3), up, glm::vec3(0), side, 0.6f, 0.4f, 10.0f);
  const float far = ssvp::ssvp_cluster_distance(glm::vec3(1e4f, 2e4f, 3e4f), up, glm::vec3(0), side, 0.6f, 0.4f, 1e5f);
  EXPECT_NEAR(near, far, 1e-6f);
}

std::vector<ClusterPoint> random_points(int n, uint32_t seed) {
  std::vector<ClusterPoint> points;
  for (int i = 0; i < n; ++i) {
    const glm::vec3 p(hash_to_unit(hash_combine(seed, 3 * i)), hash_to_unit(hash_combine(seed, 3 * i + 1)),
                      hash_to_unit(hash_combine(seed, 3 * i + 2)));
    const glm::vec3 normals[3] = {{0, 0, 1}, {1, 0, 0}, {0, -1, 0}};
    points.push_back({p, normals[i % 3]});
  }
  return points;
}

void expect_invariants(const ssvp::Clustering& c, std::size_t points) {
  ASSERT_EQ(c.assignment.size(), points);
  std::vector<uint32_t> members(c.clusters.size(), 0);
  for (uint32_t a : c.assignment) {
    ASSERT_LT(a, c.clusters.size());
    ++members[a];
  }
  for (std::size_t k = 0; k < c.clusters.size(); ++k) {
    EXPECT_GT(members[k], 0u) << "cluster " << k << " is empty";
    EXPECT_EQ(members[k], c.clusters[k].count);
    EXPECT_NEAR(glm::length(c.clusters[k].normal), 1.0f, 1e-5f);
    EXPECT_TRUE(std::isfinite(c.clusters[k].position.x + c.clusters[k].position.y + c.clusters[k].position.z));
  }
}

TEST(SsvpKMeans, EveryPointAssignedNoClusterEmptyDeterministic) {
  const auto points = random_points(256, 7);
  const ssvp::ClusterMetric metric{0.6f, 0.4f, std::sqrt(3.0f)};
  for (int k : {1, 4, 8, 16, 32}) {
    const auto a = ssvp::cluster_points(points, k, metric, {}, 42);
    expect_invariants(a, points.size());
    EXPECT_EQ(a.clusters.size(), std::size_t(k));
    const auto b = ssvp::cluster_points(points, k, metric, {}, 42);
    EXPECT_EQ(a.assignment, b.assignment);
    // Each point sits in its nearest cluster (Lloyd's fixed point, when it converged).
    if (a.iterations < 16)
      for (std::size_t i = 0; i < points.size(); ++i) {
        const auto& own = a.clusters[a.assignment[i]];
        const float d = ssvp::ssvp_cluster_distance(points[i].position, points[i].normal, own.position, own.normal,
                                                    metric.w1, metric.w2, metric.length_scale);
        for (const auto& other : a.clusters)
          EXPECT_LE(d, ssvp::ssvp_cluster_distance(points[i].position, points[i].normal, other.position, other.normal,
                                                   metric.w1, metric.w2, metric.length_scale) +
                           1e-5f);
      }
  }
}

TEST(SsvpKMeans, SeparatesFacingWallsOfACorner) {
  // Two walls meeting at an edge: points near the edge lie closer to the other wall's points than to their own
  // wall's far end; the normal term keeps each wall in its own clusters.
  std::vector<ClusterPoint> points;
  for (int i = 0; i < 64; ++i) {
    const float u = (i % 8) / 7.0f, v = (i / 8) / 7.0f;
    points.push_back({{u, v, 0.0f}, {0, 0, 1}});
    points.push_back({{0.0f, v, u}, {1, 0, 0}});
  }
  const auto c = ssvp::cluster_points(points, 4, {0.6f, 0.4f, 1.5f}, {}, 1);
  expect_invariants(c, points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    EXPECT_GT(glm::dot(points[i].normal, c.clusters[c.assignment[i]].normal), 0.7f) << i;
}

TEST(SsvpKMeans, SeedsFromThePreviousFrameAreKept) {
  const auto points = random_points(300, 3);
  const ssvp::ClusterMetric metric{0.6f, 0.4f, 1.7f};
  const auto first = ssvp::cluster_points(points, 8, metric, {}, 5);
  // Converged clusters as seeds: the same clusters come back at once, whatever the fresh seed.
  const auto again = ssvp::cluster_points(points, 8, metric, first.clusters, 999);
  ASSERT_EQ(again.clusters.size(), first.clusters.size());
  EXPECT_EQ(again.assignment, first.assignment);
  EXPECT_LE(again.iterations, 2);
}

TEST(SsvpKMeans, HardCases) {
  const ssvp::ClusterMetric metric{0.6f, 0.4f, 1.0f};
  // All points at one place with one normal: one cluster, not eight empty ones.
  std::vector<ClusterPoint> same(100, ClusterPoint{{0.5f, 0.5f, 0.5f}, {0, 0, 1}});
  auto c = ssvp::cluster_points(same, 8, metric, {}, 1);
  expect_invariants(c, same.size());
  EXPECT_EQ(c.clusters.size(), 1u);
  // Fewer points than clusters: one cluster each.
  const auto few = random_points(3, 9);
  c = ssvp::cluster_points(few, 16, metric, {}, 1);
  expect_invariants(c, few.size());
  EXPECT_EQ(c.clusters.size(), 3u);
  // Opposite normals at one point cancel: the cluster still gets a unit normal.
  std::vector<ClusterPoint> opposed = {{{0, 0, 0}, {0, 0, 1}}, {{0, 0, 0}, {0, 0, -1}}};
  c = ssvp::cluster_points(opposed, 1, metric, {}, 1);
  expect_invariants(c, opposed.size());
  // No points, or stale seeds with NaN: no clusters, no crash.
  EXPECT_TRUE(ssvp::cluster_points({}, 8, metric, {}, 1).clusters.empty());
  const std::vector<ssvp::Cluster> stale = {{glm::vec3(NAN), glm::vec3(0, 0, 1), 1}};
  c = ssvp::cluster_points(few, 2, metric, stale, 1);
  expect_invariants(c, few.size());
  EXPECT_EQ(c.clusters.size(), 2u);
}

TEST(SsvpMath, BouncingLightsAreDrawnByTheirFlux) {
  BounceLight sun = make_light(BOUNCE_LIGHT_SUN, glm::vec3(0), glm::vec3(3.0f));
  BounceLight point = make_light(BOUNCE_LIGHT_POINT, glm::vec3(0), glm::vec3(10.0f));
  const glm::vec3 centre(0.0f);
  // One draw: the light under u, weighted by 1 / its share.
  auto draw = [&](const std::vector<BounceLight>& lights, float u) {
    const std::vector<ssvp::LightDraw> draws = ssvp::draw_bouncing_lights(lights, centre, 1.0f, 1, u, {});
    return draws.empty() ? ssvp::LightDraw{} : draws.front();
  };
  // Sun: 3 W/m^2 over pi (1 m)^2 = 9.4 W; point inside: 4 pi 10 = 126 W. Each is drawn for its share of u.
  const float sun_share = 3.0f * kPi / (3.0f * kPi + 40.0f * kPi);
  EXPECT_EQ(draw({sun, point}, 0.5f * sun_share).index, 0);
  EXPECT_NEAR(draw({sun, point}, 0.5f * sun_share).weight, 1.0f / sun_share, 1e-4);
  EXPECT_EQ(draw({sun, point}, sun_share + 0.01f).index, 1);
  EXPECT_NEAR(draw({sun, point}, 0.99f).weight, 1.0f / (1.0f - sun_share), 1e-5);
  EXPECT_EQ(draw({sun, point}, 1.0f).index, 1);  // u's upper end stays on the last light
  // Far outside, the point light sends only a sliver of its flux into the sphere.
  std::memcpy(point.position, &glm::vec3(100, 0, 0)[0], 12);
  EXPECT_LT(draw({sun, point}, 0.0f).weight, 1.01f);
  // Lights that send nothing are never drawn; with none left, none bounces.
  BounceLight dark = make_light(BOUNCE_LIGHT_POINT, glm::vec3(0), glm::vec3(0.0f));
  EXPECT_TRUE(ssvp::draw_bouncing_lights(std::vector<BounceLight>{dark}, centre, 1.0f, 4, 0.5f, {}).empty());
  EXPECT_EQ(draw({dark, sun, dark}, 0.0f).index, 1);
  EXPECT_EQ(draw({dark, sun, dark}, 1.0f).index, 1);
  EXPECT_EQ(draw({dark, sun, dark}, 0.5f).weight, 1.0f);
  // A spot outside the sphere aimed away from it sends nothing.
  BounceLight spot = make_light(BOUNCE_LIGHT_SPOT, glm::vec3(0, 0, 5), glm::vec3(1000.0f));
  const float up[3] = {0, 0, 1};
  std::memcpy(spot.axis_z, up, 12);  // shining along -z, towards the sphere
  EXPECT_LT(draw({sun, spot}, 0.5f).weight, 1.1f);
  EXPECT_EQ(draw({sun, spot}, 0.5f).index, 1);
  const float down[3] = {0, 0, -1};
  std::memcpy(spot.axis_z, down, 12);  // shining along +z, away
  EXPECT_EQ(draw({sun, spot}, 0.99f).index, 0);
  EXPECT_EQ(draw({sun, spot}, 0.99f).weight, 1.0f);
}

// Several draws are systematic: a light of share p is drawn floor(n p) or ceil(n p) times, once in the list, and
// its weight m / (n p) averages to 1 over u (each light bounces with its own flux).
TEST(SsvpMath, SeveralDrawsSplitTheLightsBetweenThem) {
  std::vector<BounceLight> suns;
  for (float irradiance : {1.0f, 2.0f, 3.0f, 4.0f})
    suns.push_back(make_light(BOUNCE_LIGHT_SUN, glm::vec3(0), glm::vec3(irradiance)));
  const int n = 4;
  std::vector<double> mean_weight(suns.size(), 0.0);
  constexpr int kSteps = 1000;
  for (int step = 0; step < kSteps; ++step) {
    const std::vector<ssvp::LightDraw> draws =
        ssvp::draw_bouncing_lights(suns, glm::vec3(0.0f), 1.0f, n, (step + 0.5f) / kSteps, {});
    int total = 0;
    for (std::size_t d = 0; d < draws.size(); ++d) {
      const double share = (draws[d].index + 1) / 10.0;
      EXPECT_GE(draws[d].draws, int(std::floor(n * share)));
      EXPECT_LE(draws[d].draws, int(std::ceil(n * share)));
      EXPECT_NEAR(draws[d].weight, draws[d].draws / (n * share), 1e-5);
      if (d > 0) {
        EXPECT_LT(draws[d - 1].index, draws[d].index);
      }
      mean_weight[std::size_t(draws[d].index)] += draws[d].weight / kSteps;
      total += draws[d].draws;
    }
    EXPECT_EQ(total, n);
  }
  for (double w : mean_weight) EXPECT_NEAR(w, 1.0, 2e-3);
  // Four equal suns, four draws: each is drawn once, at its own flux.
  const std::vector<BounceLight> equal(4, suns[0]);
  const std::vector<ssvp::LightDraw> draws = ssvp::draw_bouncing_lights(equal, glm::vec3(0.0f), 1.0f, 4, 0.3f, {});
  ASSERT_EQ(draws.size(), 4u);
  for (const ssvp::LightDraw& d : draws) EXPECT_FLOAT_EQ(d.weight, 1.0f);
}

class Ssvp : public RenderFixture {
 protected:
  void SetUp() override {
    RenderFixture::SetUp();
    settings_.method = BOUNCE_METHOD_SSVP;
  }
  // A room of side `size` open at the front (-y): floor, ceiling, back and side walls, seen from the front,
  // with `light` inside.
  void room(float size, const BounceLight& light) {
    const float h = size / 2;
    add_mesh(1, {-h, -h, -h, h, -h, -h, h, h, -h, -h, h, -h,  // floor
                 -h, -h, h,  h, -h, h,  h, h, h,  -h, h, h},  // ceiling
             {0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6, 3, 2, 6, 3, 6, 7, 0, 3, 7, 0, 7, 4, 1, 5, 6, 1, 6, 2});
    set_instances({1}, {glm::mat4(1.0f)});
    set_albedo(0.7f);
    set_lights({light});
    const glm::mat4 view = glm::lookAt(glm::vec3(0, -2.2f * size, 0), glm::vec3(0), glm::vec3(0, 0, 1));
    set_camera(view, glm::perspective(glm::radians(40.0f), 1.0f, 0.01f * size, 10.0f * size), 32, 32);
  }
  // The two rooms joined by a doorway (two_rooms()), grey, lit by a point lamp in room A.
  void two_rooms_lit_in_room_a() {
    add_soup(1, two_rooms().vertices);
    set_instances({1}, {glm::mat4(1.0f)});
    set_albedo(0.8f);
    set_lights({make_light(BOUNCE_LIGHT_POINT, glm::vec3(4, 5, 3), glm::vec3(2000.0f / (4.0f * kPi)))});
  }
  // A close view of the foot of the middle wall in room B, beside the doorway, with one bounce.
  void foot_of_the_wall_in_room_b(int samples) {
    two_rooms_lit_in_room_a();
    set_camera(glm::lookAt(glm::vec3(10.3f, 2, 0.3f), glm::vec3(10.02f, 2, 0), glm::vec3(0, 0, 1)),
               glm::perspective(glm::radians(10.0f), 1.0f, 0.05f, 100.0f), 32, 32);
    settings_.samples = samples;
    settings_.bounces = 1;
  }
  // The reference for SSVP's bounces: the mean of `aov` rendered by the Topology method with exact shadow rays
  // for `vpls` VPLs. Leaves the method at SSVP.
  double ray_traced_vpls(int vpls, int aov) {
    settings_.method = BOUNCE_METHOD_TOPOLOGY;
    settings_.topology_visibility = 1;  // shadow rays
    settings_.topology_vpls = vpls;
    settings_.topology_resolution = 64;
    render(BOUNCE_AOV_INDIRECT);
    settings_.method = BOUNCE_METHOD_SSVP;
    return mean_red(read(aov));
  }
  BounceFrameInfo info() {
    BounceFrameInfo out{};
    EXPECT_EQ(bounce_frame_info(engine_, &out), BOUNCE_OK);
    return out;
  }
  // Renders; every AOV must be finite. Returns the mean Indirect.
  double render_finite() {
    const Image indirect = render(BOUNCE_AOV_INDIRECT);
    EXPECT_TRUE(all_finite(indirect));
    for (int aov = 0; aov < BOUNCE_AOV_COUNT; ++aov) EXPECT_TRUE(all_finite(read(aov))) << bounce_aov_name(aov);
    EXPECT_EQ(info().nonfinite_pixels, 0u);
    return mean_red(indirect);
  }
};

BounceLight ceiling_light(float size) {
  return make_light(BOUNCE_LIGHT_POINT, glm::vec3(0, 0, 0.3f * size), glm::vec3(10.0f * size * size));
}

TEST_F(Ssvp, ScaleFree) {
  // The same room at 1e-4, 1 and 1e4 m with the light's intensity scaled as size^2: the same image, up to
  // rounding, which can move a VPL across a cluster boundary (samples average such flips out: at 4, 3 %).
  settings_.samples = 16;
  std::vector<double> means;
  for (float size : {1e-4f, 1.0f, 1e4f}) {
    room(size, ceiling_light(size));
    means.push_back(render_finite());
  }
  ASSERT_GT(means[1], 0.0);
  EXPECT_NEAR(means[0], means[1], 0.02 * means[1]);
  EXPECT_NEAR(means[2], means[1], 0.02 * means[1]);
}

TEST_F(Ssvp, AllVplsAtOnePoint) {
  // A spot of 0.3 degrees: every VPL lands within 5 mm on the floor of a 1 m room, and lights the walls.
  BounceLight spot = make_light(BOUNCE_LIGHT_SPOT, glm::vec3(0.1f, 0.2f, 0.4f), glm::vec3(1e6f));
  spot.spot_half_angle = glm::radians(0.3f);
  room(1.0f, spot);
  settings_.ssvp_clusters = 16;
  EXPECT_GT(render_finite(), 0.0);
  EXPECT_GE(info().cluster_count, 1);
  EXPECT_LE(info().cluster_count, 16);
}

TEST_F(Ssvp, FewerVplsThanClusters) {
  room(1.0f, ceiling_light(1.0f));
  settings_.ssvp_vpls = 3;
  settings_.ssvp_clusters = 32;
  render_finite();
  EXPECT_LE(info().cluster_count, 3);
  EXPECT_GE(info().cluster_count, 1);
}

TEST_F(Ssvp, MainLightThatSeesNothing) {
  // A spot aimed through the room's open front into the void: its map holds no surface, so there are no VPLs
  // and no indirect light, and direct light is still there.
  BounceLight spot = make_light(BOUNCE_LIGHT_SPOT, glm::vec3(0, 0.3f, 0), glm::vec3(1e3f));
  const float back[3] = {0, 1, 0};
  std::memcpy(spot.axis_z, back, 12);  // shining along -y, out of the front
  spot.spot_half_angle = glm::radians(5.0f);
  room(1.0f, spot);
  EXPECT_EQ(render_finite(), 0.0);
  EXPECT_EQ(info().vpl_count, 0u);
}

// Two equal spots light the floor by the left and by the right wall: each sample bounces both (Bouncing Lights),
// so one sample lights both halves of the room alike. One draw per sample bounced one of them at twice its light:
// the first sample lit one half.
TEST_F(Ssvp, EverySampleBouncesEachLightItDraws) {
  std::vector<BounceLight> spots;
  for (float x : {-0.3f, 0.3f}) {
    BounceLight spot = make_light(BOUNCE_LIGHT_SPOT, glm::vec3(x, 0.0f, 0.4f), glm::vec3(200.0f));
    spot.spot_half_angle = glm::radians(10.0f);
    spots.push_back(spot);
  }
  room(1.0f, spots[0]);
  set_lights(spots);
  settings_.samples = 1;
  const auto halves = [&](int bouncing_lights) {
    settings_.ssvp_bouncing_lights = bouncing_lights;
    const Image indirect = render(BOUNCE_AOV_INDIRECT);
    EXPECT_TRUE(all_finite(indirect));
    double left = 0.0, right = 0.0;
    for (int y = 0; y < indirect.height; ++y)
      for (int x = 0; x < indirect.width; ++x) (x < indirect.width / 2 ? left : right) += indirect.at(x, y)[0];
    return std::pair(left, right);
  };
  const auto [left_one, right_one] = halves(1);
  const auto [left, right] = halves(4);
  std::printf("indirect left / right half: one draw %.4g / %.4g, four draws %.4g / %.4g\n", left_one, right_one, left,
              right);
  ASSERT_GT(left, 0.0);
  EXPECT_NEAR(right / left, 1.0, 0.1);
  EXPECT_NEAR(left + right, left_one + right_one, 0.1 * (left_one + right_one));  // the same light in all
}

TEST_F(Ssvp, ClusterNormalAlongAParaboloidHorizon) {
  // A sun straight down lights the floor only: the floor's clusters have normals along +z, so the floor lies
  // on their paraboloids' horizon, and the walls rise from it.
  BounceLight sun = make_light(BOUNCE_LIGHT_SUN, glm::vec3(0), glm::vec3(5.0f));
  room(1.0f, sun);
  // The ceiling would shadow the floor: take it away.
  const float h = 0.5f;
  add_mesh(1, {-h, -h, -h, h, -h, -h, h, h, -h, -h, h, -h, -h, h, h, h, h, h}, {0, 1, 2, 0, 2, 3, 3, 2, 5, 3, 5, 4});
  settings_.ssvp_clusters = 1;
  EXPECT_GT(render_finite(), 0.0);
}

// The furnace: on a sphere every VPL lights every point equally (cos cos / d^2 = 1 / 4R^2), so the
// first bounce is exact in expectation, and the second loses only what clusters emit behind their own plane
// (about 1 / 2k of it for k clusters on a sphere).
TEST_F(Ssvp, SphereFurnaceConvergesToBothBounces) {
  build_furnace();
  settings_.samples = 16;
  settings_.ssvp_vpls = 1024;
  settings_.ssvp_second_vpls = 4096;
  settings_.ssvp_clusters = 64;
  settings_.ssvp_rsm_size = 256;
  const Image indirect = render(BOUNCE_AOV_INDIRECT);
  const Image second = read(BOUNCE_AOV_SECOND_BOUNCE);
  ASSERT_TRUE(all_finite(indirect));
  const double first_bounce = mean_red(indirect) - mean_red(second);
  std::printf("furnace: first bounce %.4f (4.053), second %.4f (3.242)\n", first_bounce, mean_red(second));
  EXPECT_NEAR(first_bounce, 0.8 * 5.066, 0.02 * 0.8 * 5.066);
  EXPECT_NEAR(mean_red(second), 0.8 * 4.053, 0.02 * 0.8 * 4.053);
}

// Clustered visibility against a closed form: a 1-degree spot lights a spot of the floor (albedo 0.5) at the
// origin, so every VPL sits there; they light a wall at x = 1 facing them, half of it (y < 0) behind a low
// panel at x = 0.5. An orthographic camera between panel and wall sees the wall only.
TEST_F(Ssvp, ClusteredVisibilityAgainstTheClosedForm) {
  const float rho = 0.5f, half_angle = glm::radians(1.0f), intensity = 1e4f;
  add_mesh(1, {-2, -2, 0, 2, -2, 0, 2, 2, 0, -2, 2, 0}, {0, 1, 2, 0, 2, 3});                        // floor
  add_mesh(2, {1, -1, 0, 1, 1, 0, 1, 1, 2, 1, -1, 2}, {0, 1, 2, 0, 2, 3});                          // wall
  add_mesh(3, {0.5f, -1.5f, 0, 0.5f, 0, 0, 0.5f, 0, 0.6f, 0.5f, -1.5f, 0.6f}, {0, 1, 2, 0, 2, 3});  // panel
  set_instances({1, 2, 3}, {glm::mat4(1.0f), glm::mat4(1.0f), glm::mat4(1.0f)});
  set_albedo(rho);
  BounceLight spot = make_light(BOUNCE_LIGHT_SPOT, glm::vec3(0, 0, 1), glm::vec3(intensity));
  spot.spot_half_angle = half_angle;
  set_lights({spot});
  const glm::mat4 view = glm::lookAt(glm::vec3(0.75f, 0, 1), glm::vec3(2, 0, 1), glm::vec3(0, 0, 1));
  set_camera(view, glm::ortho(-1.0f, 1.0f, -1.0f, 1.0f, 0.01f, 1.0f), 32, 32);  // y in [-1, 1], z in [0, 2]
  settings_.samples = 8;
  settings_.ssvp_vpls = 1024;
  settings_.ssvp_clusters = 1;
  settings_.ssvp_tiling = 0;
  settings_.ssvp_blur_radius = 0;
  settings_.bounces = 1;
  const Image indirect = render(BOUNCE_AOV_INDIRECT);
  ASSERT_TRUE(all_finite(indirect));
  const double flux = rho * intensity * 2.0 * kPi * (1.0 - std::cos(half_angle));  // reflected by the floor spot
  double lit_error = 0.0, shadowed = 0.0, lit_mean = 0.0;
  int lit_count = 0, shadowed_count = 0;
  for (int py = 0; py < indirect.height; ++py)
    for (int px = 0; px < indirect.width; ++px) {
      // The camera looks along +x with up +z: image x runs along -y.
      const glm::vec3 w(1.0f, 1.0f - (px + 0.5f) / 16.0f, (py + 0.5f) / 16.0f);
      const float d = glm::length(w);
      const double expected = rho / kPi * flux / kPi * (w.z / d) * (w.x / d) / (d * d);
      const float value = indirect.at(px, py)[0];
      if (w.y > 0.1f && w.z > 0.2f) {
        lit_error += std::abs(value - expected) / expected;
        lit_mean += value / expected;
        ++lit_count;
      } else if (w.y < -0.1f && w.z < 1.0f && w.z > 0.1f) {
        shadowed += value / expected;
        ++shadowed_count;
      }
    }
  std::printf("lit: mean ratio %.4f, mean |error| %.4f; shadowed: mean ratio %.4f\n", lit_mean / lit_count,
              lit_error / lit_count, shadowed / shadowed_count);
  EXPECT_NEAR(lit_mean / lit_count, 1.0, 0.03);
  EXPECT_LT(lit_error / lit_count, 0.05);
  EXPECT_LT(shadowed / shadowed_count, 0.02);
}

TEST_F(Ssvp, OneBounceHasNoSecondBounce) {
  room(1.0f, ceiling_light(1.0f));
  settings_.bounces = 1;
  EXPECT_GT(render_finite(), 0.0);
  EXPECT_EQ(mean_red(read(BOUNCE_AOV_SECOND_BOUNCE)), 0.0);
}

TEST_F(Ssvp, SameSeedSameImage) {
  room(1.0f, ceiling_light(1.0f));
  settings_.samples = 2;
  settings_.ssvp_temporal_seeding = 0;
  const Image a = render(BOUNCE_AOV_INDIRECT);
  const Image b = render(BOUNCE_AOV_INDIRECT);
  EXPECT_EQ(a.values, b.values);
}

// The second bounce against ray-traced VPLs (the Topology renderer with shadow rays: exact indirect visibility)
// on a courtyard half under a roof, lit by a high sun, with one cluster mixing the sunlit roof top and the sunlit
// floor. A cluster that acted as one light at its centre (in mid-air between roof and floor) sent the roof's
// light into the roof's own underside and from there onto the shaded floor: 2.8x the rays' second bounce here.
TEST_F(Ssvp, SecondBounceMatchesRayTracedVpls) {
  add_mesh(1, {-5, -5, 0, 5, -5, 0, 5, 5, 0, -5, 5, 0}, {0, 1, 2, 0, 2, 3});    // floor
  add_mesh(2, {-5, -5, 3, -1, -5, 3, -1, 5, 3, -5, 5, 3}, {0, 1, 2, 0, 2, 3});  // roof
  set_instances({1, 2}, {glm::mat4(1.0f), glm::mat4(1.0f)});
  set_albedo(0.8f);
  set_sun(glm::vec3(0.3f, 0.2f, 1.0f));
  set_camera(glm::lookAt(glm::vec3(-3, -9, 1.5f), glm::vec3(-3, 0, 1.2f), glm::vec3(0, 0, 1)),
             glm::perspective(glm::radians(50.0f), 1.0f, 0.05f, 100.0f), 32, 32);
  settings_.samples = 16;
  settings_.bounces = 2;
  const double rays = ray_traced_vpls(8192, BOUNCE_AOV_SECOND_BOUNCE);
  settings_.ssvp_vpls = 1024;
  settings_.ssvp_second_vpls = 4096;
  settings_.ssvp_clusters = 1;
  render(BOUNCE_AOV_INDIRECT);
  const double ssvp_second = mean_red(read(BOUNCE_AOV_SECOND_BOUNCE));
  std::printf("courtyard second bounce: SSVP %.5f, ray-traced VPLs %.5f (ratio %.3f)\n", ssvp_second, rays,
              ssvp_second / rays);
  ASSERT_GT(rays, 0.0);
  EXPECT_NEAR(ssvp_second / rays, 1.0, 0.3);
}

TEST_F(Ssvp, ParaboloidEyeOnALitSurface) {
  // A sunlit floor with a closed block standing on it: one cluster's mean lies inside the block. A paraboloid map
  // seen from there hides the whole scene, and the wall the floor lights went black; seen from the member nearest
  // the mean it matches ray-traced VPLs.
  add_mesh(1, {-8, -8, 0, 8, -8, 0, 8, 8, 0, -8, 8, 0}, {0, 1, 2, 0, 2, 3});  // floor
  add_mesh(
      2, {-2, -2, 0, 2, -2, 0, -2, 2, 0, 2, 2, 0, -2, -2, 2, 2, -2, 2, -2, 2, 2, 2, 2, 2},
      {4, 5, 7, 4, 7, 6, 0, 2, 3, 0, 3, 1, 0, 1, 5, 0, 5, 4, 3, 2, 6, 3, 6, 7, 2, 0, 4, 2, 4, 6, 1, 3, 7, 1, 7, 5});
  add_mesh(3, {-8, 6, 0, 8, 6, 0, 8, 6, 4, -8, 6, 4}, {0, 2, 1, 0, 3, 2});  // a wall facing the block, unlit
  set_instances({1, 2, 3}, {glm::mat4(1.0f), glm::mat4(1.0f), glm::mat4(1.0f)});
  set_albedo(0.8f);
  set_sun(glm::vec3(0.3f, 0.2f, 1.0f));
  set_camera(glm::lookAt(glm::vec3(0, 2.5f, 1.5f), glm::vec3(0, 6, 1.5f), glm::vec3(0, 0, 1)),
             glm::perspective(glm::radians(60.0f), 1.0f, 0.05f, 100.0f), 32, 32);
  settings_.samples = 16;
  settings_.bounces = 1;
  const double rays = ray_traced_vpls(8192, BOUNCE_AOV_INDIRECT);
  settings_.ssvp_vpls = 1024;
  settings_.ssvp_clusters = 1;
  const double ssvp = mean_red(render(BOUNCE_AOV_INDIRECT));
  std::printf("wall lit by the floor: SSVP %.5f, ray-traced VPLs %.5f (ratio %.3f)\n", ssvp, rays, ssvp / rays);
  ASSERT_GT(rays, 0.0);
  EXPECT_NEAR(ssvp / rays, 1.0, 0.3);
}

TEST_F(Ssvp, VplImportanceFindsTheRoomASunShinesInto) {
  // A closed room on a wide ground, lit only by the sun through a hole in its roof. The sun's reflective shadow
  // map spans the whole scene, so the paper's evenly spread VPLs put one in 150 into the room, and clusters that
  // mix them with the ground outside shadow them; VPLs drawn by importance land on the lit patch inside.
  add_mesh(1, {-6, -6, 0, 6, -6, 0, 6, 6, 0, -6, 6, 0}, {0, 1, 2, 0, 2, 3});  // ground, and the room's floor
  add_mesh(2, {-2,    -2,    0, 2,    -2,    0, 2,    2,    0, -2,    2,    0,
               -2,    -2,    3, 2,    -2,    3, 2,    2,    3, -2,    2,    3,               // walls' corners
               -0.5f, -0.5f, 3, 0.5f, -0.5f, 3, 0.5f, 0.5f, 3, -0.5f, 0.5f, 3},              // the hole's
           {0, 1, 5, 0, 5, 4, 1, 2, 6,  1, 6,  5, 2, 3, 7,  2, 7,  6,  3, 0, 4, 3, 4, 7,     // walls
            4, 5, 9, 4, 9, 8, 5, 6, 10, 5, 10, 9, 6, 7, 11, 6, 11, 10, 7, 4, 8, 7, 8, 11});  // roof around the hole
  set_instances({1, 2}, {glm::mat4(1.0f), glm::mat4(1.0f)});
  set_albedo(0.8f);
  set_sun(glm::vec3(0.1f, 0.05f, 1.0f));
  set_camera(glm::lookAt(glm::vec3(0, -1.8f, 1.5f), glm::vec3(0, 2, 1.2f), glm::vec3(0, 0, 1)),
             glm::perspective(glm::radians(70.0f), 1.0f, 0.05f, 100.0f), 32, 32);
  settings_.samples = 16;
  settings_.bounces = 1;
  const double rays = ray_traced_vpls(4096, BOUNCE_AOV_INDIRECT);
  std::vector<double> ssvp;
  for (int importance : {0, 1}) {
    settings_.ssvp_importance = importance;
    ssvp.push_back(mean_red(render(BOUNCE_AOV_INDIRECT)));
  }
  std::printf(
      "room lit through its roof: SSVP %.5f (evenly spread VPLs), %.5f (by importance), ray-traced VPLs "
      "%.5f\n",
      ssvp[0], ssvp[1], rays);
  ASSERT_GT(rays, 0.0);
  EXPECT_NEAR(ssvp[1] / rays, 1.0, 0.2);
}

// Issue 15's open ground in small: a 1 m box on a wide sunlit ground, a few pixels of a wide view, its faces toward
// the camera in its own shadow and lit by the ground around them. VPL Importance leaves out the candidates whose
// light reaches none of its view samples; with only its 8 x 8 probes, those that light only the box were left out
// whenever no probe fell on it: 0.66 of the ray-traced VPLs' first bounce. Weighed again at 16 x 16 probes where
// the 8 x 8 see nothing: 1.02.
TEST_F(Ssvp, VplImportanceKeepsTheLightOfASmallObjectInAWideView) {
  add_plane(1, 60.0f);
  add_mesh(
      2, {-0.5f, -0.5f, 0, 0.5f, -0.5f, 0, 0.5f, 0.5f, 0, -0.5f, 0.5f, 0,
          -0.5f, -0.5f, 1, 0.5f, -0.5f, 1, 0.5f, 0.5f, 1, -0.5f, 0.5f, 1},
      {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7});
  set_instances({1, 2}, {glm::mat4(1.0f), glm::mat4(1.0f)});
  set_albedo(0.6f);
  set_sun(glm::vec3(0.6f, 0.5f, 0.6f));
  set_camera(glm::lookAt(glm::vec3(-5.0f, -7.0f, 2.5f), glm::vec3(0.0f, 0.0f, 0.5f), glm::vec3(0, 0, 1)),
             glm::perspective(glm::radians(60.0f), 1.0f, 0.05f, 100.0f), 32, 32);
  settings_.samples = 16;
  settings_.bounces = 1;
  const double rays = ray_traced_vpls(16384, BOUNCE_AOV_INDIRECT);
  const double ssvp = mean_red(render(BOUNCE_AOV_INDIRECT));
  std::printf("small box in a wide view, first bounce: SSVP %.5f, ray-traced VPLs %.5f (ratio %.3f)\n", ssvp, rays,
              ssvp / rays);
  ASSERT_GT(rays, 0.0);
  EXPECT_NEAR(ssvp / rays, 1.0, 0.15);
}

// Issue 15's sunlit interior in small: a closed room lit only by a sun through slatted window blinds, on a wide
// sunlit ground. Much of its second bounce reaches the view through surfaces that the first-bounce clusters'
// eyes do not see, or comes from VPLs that VPL Importance leaves out (the slats' tops, the ground outside), which
// the paper's propagation (Sec. II-B) misses: 0.68 of Cycles' on the budget's sunlit interior. Traced, and each
// shadowed by its own cluster's map, at the default settings: within 15 % of ray-traced VPLs (1.07 here). 64
// samples: at 16 the second bounce moves with the seed from 0.64 to 1.38 of the rays' (seeds 0-2, with and
// without guided candidates); at 256 both give 0.90-1.03.
TEST_F(Ssvp, SecondBounceOfARoomLitThroughBlinds) {
  add_soup(1, room_with_window(true).vertices);
  set_instances({1}, {glm::mat4(1.0f)});
  set_albedo(0.7f);
  set_sun(glm::vec3(0.3f, -0.8f, 0.7f));
  set_camera(glm::lookAt(glm::vec3(5.6f, 0.3f, 2.0f), glm::vec3(1.0f, 3.5f, 0.8f), glm::vec3(0, 0, 1)),
             glm::perspective(glm::radians(70.0f), 1.0f, 0.05f, 100.0f), 32, 32);
  settings_.samples = 16;
  settings_.bounces = 2;
  const double rays = ray_traced_vpls(8192, BOUNCE_AOV_SECOND_BOUNCE);
  settings_.samples = 64;
  render(BOUNCE_AOV_INDIRECT);
  const double ssvp_second = mean_red(read(BOUNCE_AOV_SECOND_BOUNCE));
  std::printf("room lit through blinds, second bounce: SSVP %.5f, ray-traced VPLs %.5f (ratio %.3f)\n", ssvp_second,
              rays, ssvp_second / rays);
  ASSERT_GT(rays, 0.0);
  EXPECT_NEAR(ssvp_second / rays, 1.0, 0.15);
}

// The two rooms joined by a doorway, seen from the unlit room B with the lamp in room A: room B's side walls are
// lit by the floor patch the lamp reaches through the doorway and by room A's walls through it. Clustered
// visibility let room A's light through the thin middle wall onto them: a texel centre's depth with a tolerance of
// a footprint x the tangent of the incidence passed the receivers just behind the wall, and members whose
// cluster's eye stood beyond the doorway lit what that eye sees (the budget's two rooms: 1.8 times Cycles on the
// side walls; this test: 1.24 before the fix, 1.02 with it). The outer thirds of the view against ray-traced VPLs.
TEST_F(Ssvp, DoorwayLightStaysOffTheWallsBesideIt) {
  two_rooms_lit_in_room_a();
  set_camera(glm::lookAt(glm::vec3(19.5f, 5, 2), glm::vec3(10, 5, 1.5f), glm::vec3(0, 0, 1)),
             glm::perspective(glm::radians(70.0f), 16.0f / 9.0f, 0.05f, 100.0f), 64, 36);
  settings_.samples = 16;
  settings_.bounces = 1;
  const auto outer_thirds = [](const Image& image) {
    double sum = 0.0;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x)
        if (x < image.width / 3 || x >= image.width - image.width / 3) sum += image.at(x, y)[0];
    return sum;
  };
  settings_.method = BOUNCE_METHOD_TOPOLOGY;
  settings_.topology_visibility = 1;  // shadow rays
  settings_.topology_vpls = 8192;
  settings_.topology_resolution = 64;
  const double rays = outer_thirds(render(BOUNCE_AOV_INDIRECT));
  settings_.method = BOUNCE_METHOD_SSVP;
  const double ssvp = outer_thirds(render(BOUNCE_AOV_INDIRECT));
  std::printf("room B's side walls: SSVP %.5f, ray-traced VPLs %.5f (ratio %.3f)\n", ssvp, rays, ssvp / rays);
  ASSERT_GT(rays, 0.0);
  EXPECT_NEAR(ssvp / rays, 1.0, 0.15);
}

// The same two rooms, their middle wall a single face: room B's floor within a few centimetres of the wall lay
// within half a texel's footprint of the wall's plane in the maps of room A's eyes, which counted it as in front of
// the wall and let room A's light through (the budget's two rooms: 3-16 times Cycles in the last 5 pixels before
// the corner). The foot of the wall in room B, beside the doorway, against ray-traced VPLs. VPL
// Importance is off: with it, VPLs join the clusters whose eyes agree with them on the view, and a view this close
// leaves no VPL in a cluster whose eye looks through the wall. 62 times the rays' light before, 2.2 times with
// the maps alone: what is left is the rule that receivers behind a map's hemisphere count as seen (README, Accuracy:
// 1.18 times with them counted as hidden); 1.16 with Ray Checks (RayChecksTakeTheMapsToTheShadowRays).
TEST_F(Ssvp, SingleFacedWallKeepsTheLitRoomsLightOnItsSide) {
  foot_of_the_wall_in_room_b(16);
  const double rays = ray_traced_vpls(8192, BOUNCE_AOV_INDIRECT);
  settings_.ssvp_importance = 0;
  const double ssvp = mean_red(render(BOUNCE_AOV_INDIRECT));
  std::printf("room B's floor at the foot of the wall: SSVP %.5f, ray-traced VPLs %.5f (ratio %.3f)\n", ssvp, rays,
              ssvp / rays);
  ASSERT_GT(rays, 0.0);
  EXPECT_LT(ssvp / rays, 3.0);
}

// Ray Checks: a shadow ray from the VPL itself checks the map's verdict on a share of the VPL-pixel pairs, and the
// difference, taken the inverse share times, corrects it (a control variate, as Forward Light Cuts' and the Topology
// method's). The foot of the single-faced wall above, where the maps of room A's eyes let its light through: every
// pair checked is SSVP with a shadow ray per pair; a sixteenth checked has its mean (1.003 of it at 128 samples,
// the maps 1.66), and the image repeats for a seed.
TEST_F(Ssvp, RayChecksTakeTheMapsToTheShadowRays) {
  foot_of_the_wall_in_room_b(32);
  settings_.ssvp_importance = 0;
  const auto mean_with = [&](float share) {
    settings_.ssvp_ray_checks = share;
    return render_finite();
  };
  const double rays = mean_with(1.0f), maps = mean_with(0.0f), checked = mean_with(0.0625f);
  std::printf(
      "room B's floor at the foot of the wall, mean Indirect: the maps %.5g, a shadow ray per pair %.5g (%.3f), a "
      "sixteenth checked %.5g (%.3f)\n",
      maps, rays, maps / rays, checked, checked / rays);
  EXPECT_GT(maps / rays, 1.3);
  EXPECT_NEAR(checked / rays, 1.0, 0.1);
  const Image image = render(BOUNCE_AOV_INDIRECT);
  EXPECT_EQ(render(BOUNCE_AOV_INDIRECT).values, image.values);
  EXPECT_GE(*std::min_element(image.values.begin(), image.values.end()), 0.0f) << "the mean of signed corrections";
  settings_.bounces = 2;
  const Image second = render(BOUNCE_AOV_SECOND_BOUNCE);
  EXPECT_GE(*std::min_element(second.values.begin(), second.values.end()), 0.0f);
  settings_.ssvp_ray_checks = 1e-12f;
  EXPECT_TRUE(all_finite(render())) << "a check now and then, weighed 1e12 times";
}

// Maps seen from lights halve until they fit their memory budget (issue 18: SSVP with every costly setting at its
// maximum peaked at 5.4 GiB, a point light's reflective shadow map at RSM Size 4096 being six G-buffer faces of
// 4096^2, 5.2 GB). With the 1 GiB budget that RSM becomes six faces of 1024^2 (327 MB); a spot light's one face
// keeps 4096 (872 MB); a size that fits stays; nothing goes below the floor.
TEST(LightMapMemory, MapsHalveUntilTheyFitTheirBudget) {
  constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
  EXPECT_EQ(size_within_budget(4096, 64, 6, kGBufferBytesPerTexel, kGiB), 1024);
  EXPECT_EQ(size_within_budget(4096, 64, 1, kGBufferBytesPerTexel, kGiB), 4096);
  EXPECT_EQ(size_within_budget(512, 64, 6, kGBufferBytesPerTexel, kGiB), 512);
  EXPECT_EQ(size_within_budget(4096, 64, 1e9, 4.0, kGiB), 64);
  EXPECT_EQ(size_within_budget(100, 64, 1e9, 4.0, 1.0), 50);  // halving stops once at or below the floor
}

}  // namespace
}  // namespace bounce::test
