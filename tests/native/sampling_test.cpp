// Sample sequences: centred first samples, stratification, uniformity, light sample points inside the light, and the
// resampling of candidate VPLs by importance.
#include <gtest/gtest.h>

#include <cmath>

#include "cpu/sky_guide.h"
#include "cpu/vpls.h"
#include "passes/shadows/shadow_pass.h"
#include "radiometry.h"
#include "renderer.h"
#include "sampling.h"

namespace bounce {
namespace {

TEST(Sampling, R2StartsAtTheCentreAndStaysInTheUnitSquare) {
  EXPECT_EQ(r2_point(0, glm::vec2(0.0f)), glm::vec2(0.5f));
  for (uint32_t i = 0; i < 1000; ++i) {
    const glm::vec2 p = r2_point(i, glm::vec2(0.3f, 0.9f));
    EXPECT_GE(p.x, 0.0f);
    EXPECT_LT(p.x, 1.0f);
    EXPECT_GE(p.y, 0.0f);
    EXPECT_LT(p.y, 1.0f);
  }
}

// Any 2^m points from a multiple of 2^m fill each of the 2^m intervals of each of the first two coordinates once,
// and every 2^(2m) points each of the (2^m)^2 cells of those two; 64 points fill each of the 4^3 cells of all
// three. Scrambled or not, and always in [0,1).
TEST(Sampling, SobolPointsAreStratifiedAndStayInTheUnitCube) {
  for (const glm::uvec3& scramble : {glm::uvec3(0u), glm::uvec3(0x9e3779b9u, 0x7f4a7c15u, 0xdeadbeefu)}) {
    for (uint32_t first : {0u, 16u, 4096u}) {
      for (int dimension = 0; dimension < 3; ++dimension) {
        std::vector<int> hits(16, 0);
        for (uint32_t i = first; i < first + 16; ++i) ++hits[std::size_t(sobol_point(i, scramble)[dimension] * 16)];
        for (int h : hits) EXPECT_EQ(h, 1) << "points " << first << "+, dimension " << dimension;
      }
      std::vector<int> squares(16, 0);
      for (uint32_t i = first; i < first + 16; ++i) {
        const glm::ivec2 c(sobol_point(i, glm::uvec2(scramble)) * 4.0f);
        ++squares[std::size_t(c.x * 4 + c.y)];
      }
      for (int h : squares) EXPECT_EQ(h, 1) << "points " << first << "+";
    }
    std::vector<int> cells(64, 0);
    for (uint32_t i = 0; i < 64; ++i) {
      const glm::ivec3 c(sobol_point(i, scramble) * 4.0f);
      ++cells[std::size_t(c.x * 16 + c.y * 4 + c.z)];
    }
    for (int h : cells) EXPECT_EQ(h, 1);
  }
  for (uint32_t i = 0; i < 1000; ++i) {
    const glm::vec3 p = sobol_point(i, glm::uvec3(i * 0x9e3779b9u, ~i, 0xffffffffu));
    for (int d = 0; d < 3; ++d) {
      EXPECT_GE(p[d], 0.0f);
      EXPECT_LT(p[d], 1.0f);
    }
  }
}

TEST(Sampling, ConcentricDiskIsUniform) {
  // Equal-area rings and sectors must receive equal counts (chi-square, 16 cells, 15 dof: 99.9 % at 37.7).
  const int n = 64000, rings = 4, sectors = 4;
  std::vector<int> counts(rings * sectors, 0);
  for (int i = 0; i < n; ++i) {
    const glm::vec2 d = concentric_disk(r2_point(static_cast<uint32_t>(i), glm::vec2(0.1f, 0.2f)));
    const float r2 = glm::dot(d, d);
    ASSERT_LE(r2, 1.0f + 1e-5f);
    const int ring = std::min(rings - 1, static_cast<int>(r2 * rings));
    const float angle = std::atan2(d.y, d.x) + 3.14159265f;
    const int sector = std::min(sectors - 1, static_cast<int>(angle / (2 * 3.14159265f) * sectors));
    ++counts[ring * sectors + sector];
  }
  const double expected = static_cast<double>(n) / counts.size();
  double chi2 = 0.0;
  for (int c : counts) chi2 += (c - expected) * (c - expected) / expected;
  EXPECT_LT(chi2, 37.7);
  EXPECT_EQ(concentric_disk(glm::vec2(0.5f)), glm::vec2(0.0f));
}

TEST(Sampling, LightSamplePointsLieOnTheLight) {
  BounceLight rect{};
  rect.type = BOUNCE_LIGHT_AREA_RECT;
  rect.position[2] = 2.0f;
  rect.axis_x[0] = rect.axis_y[1] = rect.axis_z[2] = 1.0f;
  rect.half_size[0] = 0.5f;
  rect.half_size[1] = 0.25f;
  EXPECT_EQ(light_shadow_origin(rect, 0, 7, 0, 1.0f), glm::vec3(0, 0, 2));
  for (uint32_t s = 1; s < 200; ++s) {
    const glm::vec3 p = light_shadow_origin(rect, s, 7, 0, 1.0f);
    EXPECT_LE(std::abs(p.x), 0.5f + 1e-6f);
    EXPECT_LE(std::abs(p.y), 0.25f + 1e-6f);
    EXPECT_FLOAT_EQ(p.z, 2.0f);
    EXPECT_EQ(light_shadow_origin(rect, s, 7, 0, 0.0f), glm::vec3(0, 0, 2));  // softness 0: hard shadows
  }
  BounceLight sun = rect;
  sun.type = BOUNCE_LIGHT_SUN;
  sun.sun_angle = 0.1f;
  for (uint32_t s = 1; s < 200; ++s) {
    const glm::vec3 d = light_shadow_origin(sun, s, 7, 0, 1.0f);
    EXPECT_NEAR(glm::length(d), 1.0f, 1e-5f);
    EXPECT_GE(d.z, std::cos(0.05f) - 1e-6f);
  }
}

// Found by the scene fuzzer (seed 21, case 3338: 555 NaN pixels in SSVP): with u near 1, next + u rounded up to
// `count` in float, so the last draw passed every candidate and took the last one, whose importance was 0: an
// infinite weight. Every draw must land on a candidate that can be drawn, with a finite weight, and the weights
// must still add up to the candidates' count (the estimate stays unbiased).
TEST(Resample, LargestOffsetDrawsOnlyDrawableCandidates) {
  std::vector<float> importance(128, 0.0f);
  for (std::size_t i = 0; i < 39; ++i) importance[i * 3] = 1e-11f * float(1 + i % 7);
  const float largest_u = 1.0f - 1.0f / 16777216.0f;  // hash_to_unit's largest value
  for (int count : {256, 2048, 16384})
    for (float share : {0.0f, 0.1f})
      for (float u : {0.0f, 0.5f, 0.999994874f, largest_u}) {
        double weight_of_drawable = 0.0;
        for (const cpu::Draw& draw : cpu::resample(importance, count, share, u)) {
          ASSERT_LT(draw.index, importance.size());
          ASSERT_TRUE(std::isfinite(draw.weight)) << "count " << count << ", u " << u << ", share " << share;
          ASSERT_TRUE(share > 0.0f || importance[draw.index] > 0.0f) << "a draw of a candidate of no importance";
          weight_of_drawable += draw.weight;
        }
        // Each draw weighs 1 / (count p): summed, about the number of candidates that can be drawn.
        EXPECT_NEAR(weight_of_drawable, share > 0.0f ? 128.0 : 39.0, share > 0.0f ? 128.0 * 0.5 : 39.0 * 0.5)
            << "count " << count << ", u " << u;
      }
}

// A guided emission point is drawn with the density it reports: over many draws, the mean of f / density is the
// integral of f over the square, for any f (here the indicator of a quarter, where the guide learned nothing, and
// of the cell it learned most), and points fall in the learned cell as often as its density says.
TEST(EmissionGuide, DrawsWithTheDensityItReports) {
  cpu::EmissionGuide guide;
  EXPECT_TRUE(guide.uniform());
  guide.learn({0.8f, 0.1f}, 5.0f);
  guide.learn({0.9f, 0.15f}, 1.0f);
  guide.learn({0.2f, 0.7f}, 0.0f);  // no importance: nothing learned
  guide.update();
  ASSERT_FALSE(guide.uniform());
  const int n = 1 << 18, cells = cpu::EmissionGuide::kCellsPerSide;
  const auto in_cell = [&](glm::vec2 u, glm::vec2 of) {
    return glm::ivec2(u * float(cells)) == glm::ivec2(of * float(cells));
  };
  double quarter = 0.0, learned_cell = 0.0;
  int in_learned = 0;
  for (int i = 0; i < n; ++i) {
    const glm::vec2 within = r2_point(uint32_t(i) + 1u, glm::vec2(0.25f, 0.75f));
    const auto sample = guide.sample((float(i) + 0.5f) / float(n), within);
    ASSERT_GT(sample.density, 0.0f);
    ASSERT_TRUE(sample.emission.x >= 0.0f && sample.emission.x < 1.0f && sample.emission.y >= 0.0f &&
                sample.emission.y < 1.0f);
    if (sample.emission.x < 0.5f && sample.emission.y >= 0.5f) quarter += 1.0 / sample.density;
    if (in_cell(sample.emission, {0.8f, 0.1f})) learned_cell += 1.0 / sample.density, ++in_learned;
  }
  EXPECT_NEAR(quarter / n, 0.25, 0.01);
  EXPECT_NEAR(learned_cell / n, 1.0 / (cells * cells), 0.01 / (cells * cells));
  // 5/6 of the learned share, 3/4 of all, plus the uniform share's 1/4 of one cell.
  const double expected = 0.75 * 5.0 / 6.0 + 0.25 / (cells * cells);
  EXPECT_NEAR(double(in_learned) / n, expected, 0.01);
}

// The world's paths leave their disk with the density the landing guide reports: over many draws the mean of
// f / density is the integral of f over the disk relative to its area, for f = 1, the indicator of a half-disk
// and that of the learned cell's shadow, and the learned cell's shadow gets the share of the draws it should.
TEST(LandingGuide, DrawsWithTheDensityItReports) {
  const glm::vec3 lo(-1.0f, 0.0f, 0.0f), hi(3.0f, 2.0f, 1.0f), centre = 0.5f * (lo + hi);
  const float radius = 0.5f * glm::length(hi - lo);
  cpu::LandingGuide guide(lo, hi);
  EXPECT_TRUE(guide.uniform());
  // Two paths of the world (light 1 of one lamp and one direction) and one of the lamp, which teaches nothing.
  const std::vector<cpu::Vpl> paths = {{{2.9f, 1.9f, 0.05f}, {0, 0, 1}, glm::vec3(1.0f), 1, 1},
                                       {{2.95f, 1.95f, 0.1f}, {0, 0, 1}, glm::vec3(1.0f), 2, 1},
                                       {{0.0f, 1.0f, 0.5f}, {0, 0, 1}, glm::vec3(1.0f), 1, 1},
                                       {{-0.9f, 0.1f, 0.1f}, {0, 0, 1}, glm::vec3(1.0f), 1, 0}};
  guide.learn(paths, std::vector<float>{2.0f, 1.0f, 1.0f, 9.0f}, {1, 1});
  guide.update();
  ASSERT_FALSE(guide.uniform());
  const glm::vec3 direction = glm::normalize(glm::vec3(-0.3f, -0.2f, -1.0f));  // from above, as a sky's
  const glm::vec3 x = glm::normalize(glm::cross(direction, glm::vec3(1, 0, 0))), y = glm::cross(direction, x);
  const glm::vec3 disk_centre = centre - 2.0f * radius * direction;
  // The learned cell's shadow on the disk: lines along the direction that pass near the hottest landing.
  const auto shadows_corner = [&](glm::vec3 p) {
    const glm::vec3 closest = p + direction * glm::dot(glm::vec3(2.9f, 1.9f, 0.05f) - p, direction);
    return glm::length(closest - glm::vec3(2.9f, 1.9f, 0.05f)) < 0.05f;
  };
  const int n = 1 << 20;
  double all = 0.0, half = 0.0, corner = 0.0, uniform_density = 0.0;
  int in_corner = 0;
  for (int i = 0; i < n; ++i) {
    const glm::vec2 u = r2_point(uint32_t(i) + 1u, glm::vec2(0.25f, 0.75f));
    const float r = radius * std::sqrt(u.x), phi = 2.0f * kPi * u.y;
    const glm::vec3 uniform_origin = disk_centre + r * (std::cos(phi) * x + std::sin(phi) * y);
    const float choice = (float(i % 997) + 0.5f) / 997.0f, pick = (float(i) + 0.5f) / float(n);
    const glm::vec3 within(float(i % 89) / 89.0f, u.x, u.y);
    const auto drawn = guide.origin(uniform_origin, disk_centre, direction, radius, choice, pick, within);
    uniform_density += guide.origin(uniform_origin, disk_centre, direction, radius, 0.0f, 0.0f, within).density;
    if (!(drawn.density > 0.0f)) continue;
    all += 1.0 / drawn.density;
    if (glm::dot(drawn.point - disk_centre, x) > 0.0f) half += 1.0 / drawn.density;
    if (shadows_corner(drawn.point)) corner += 1.0 / drawn.density, ++in_corner;
  }
  const double corner_area = kPi * 0.05 * 0.05 / (kPi * radius * radius);
  EXPECT_NEAR(all / n, 1.0, 0.01);
  EXPECT_NEAR(half / n, 0.5, 0.01);
  EXPECT_NEAR(corner / n, corner_area, 0.05 * corner_area);
  EXPECT_NEAR(uniform_density / n, 1.0, 0.01);
  // The corner's landings hold 3/4 of what was learned, and the guided share is 3/4 of the draws.
  EXPECT_GT(double(in_corner) / n, 0.2);
}

// Paths go to the classes of lights by the root of the second moment of what one of their paths estimates, mixed
// with a quarter by power: a lamp whose light rides on one path in a hundred gets more paths than one whose every
// path lights a little, though it gives less light; the world's directions share their class's paths by power; a
// path's importance is its VPLs' together; and a render's first sample goes by power alone.
TEST(PathShares, SharePathsByTheirImportancesSecondMoment) {
  BounceLight lamp{};
  lamp.type = BOUNCE_LIGHT_POINT;
  lamp.intensity[0] = lamp.intensity[1] = lamp.intensity[2] = 1.0f;
  BounceLight sky = lamp;
  sky.type = BOUNCE_LIGHT_SUN;
  sky.axis_z[2] = 1.0f;
  const float radius = 2.0f;  // a sky direction's power, pi r^2, is then a point light's, 4 pi
  const std::vector<BounceLight> lights = {lamp, lamp, sky, sky};
  const cpu::LightKinds kinds{2, 2};
  cpu::PathShares shares;
  shares.reset(2);
  const std::vector<double> first = shares.weights(lights, kinds, radius);
  ASSERT_EQ(first.size(), 4u);
  for (double w : first) EXPECT_NEAR(w / first[0], 1.0, 1e-6);
  // 100 paths per light: lamp 0's every path gives 1, lamp 1's first path 20 and the rest nothing, the sky's paths
  // two VPLs of 0.5 each.
  std::vector<cpu::Vpl> candidates;
  std::vector<float> importance;
  for (uint32_t l = 0; l < 4; ++l)
    for (int i = 0; i < 100; ++i)
      for (uint32_t bounce = 1; bounce <= (l >= 2 ? 2u : 1u); ++bounce) {
        candidates.push_back({glm::vec3(0.0f), glm::vec3(0, 0, 1), glm::vec3(1.0f), bounce, l});
        importance.push_back(l == 0 ? 1.0f : l == 1 ? (i == 0 ? 20.0f : 0.0f) : 0.5f);
      }
  shares.learn(candidates, importance, first, 400, kinds);
  const std::vector<double> learned = shares.weights(lights, kinds, radius);
  // Second moments 100 x 100, 100 x 400 and, for the sky's 200 paths, 200 x 200: roots 100, 200 and 200 share
  // three quarters; the power's quarter goes a quarter to each light.
  const double total = learned[0] + learned[1] + learned[2] + learned[3];
  EXPECT_NEAR(learned[0] / total, 0.75 * 0.2 + 0.0625, 1e-6);
  EXPECT_NEAR(learned[1] / total, 0.75 * 0.4 + 0.0625, 1e-6);
  EXPECT_NEAR(learned[2] / total, 0.75 * 0.2 + 0.0625, 1e-6);
  EXPECT_NEAR(learned[3] / total, 0.75 * 0.2 + 0.0625, 1e-6);
}

// The sky guide draws a box's directions with the density it reports: over many draws the mean of f / pdf is the
// integral of f over the bins learned, its pdf() agrees with each draw's, it guides only the boxes that learned,
// a side reads what the other side learned, and what it learns does not depend on the order.
TEST(SkyGuide, DrawsWithTheDensityItReports) {
  cpu::SkyGuide guide(glm::vec3(0.0f), glm::vec3(4.0f, 4.0f, 2.0f));
  const glm::vec3 x(0.2f, 0.3f, 0.1f), elsewhere(3.8f, 3.7f, 1.9f);
  const glm::vec3 window = glm::normalize(glm::vec3(0.2f, -1.0f, 0.4f)), up(0.0f, 0.0f, 1.0f);
  for (int i = 0; i < 300; ++i) guide.learn(1, x, window, 0.5f);
  for (int i = 0; i < 50; ++i) guide.learn(1, x, up, 0.1f);
  guide.update();
  EXPECT_TRUE(guide.guides(0, x));
  EXPECT_FALSE(guide.guides(1, x));  // its own side learned it
  EXPECT_FALSE(guide.guides(0, elsewhere));
  EXPECT_FALSE(guide.draw(0, elsewhere, 0.5f, {0.5f, 0.5f}));
  const int n = 1 << 18;
  double all = 0.0, near_window = 0.0;
  int agree = 0;
  for (int i = 0; i < n; ++i) {
    const glm::vec2 within = r2_point(uint32_t(i) + 1u, glm::vec2(0.25f, 0.75f));
    const auto drawn = guide.draw(0, x, (float(i) + 0.5f) / float(n), within);
    ASSERT_TRUE(drawn);
    ASSERT_GT(drawn->pdf, 0.0f);
    ASSERT_NEAR(glm::length(drawn->direction), 1.0f, 1e-4f);
    agree += std::abs(guide.pdf(0, x, drawn->direction) / drawn->pdf - 1.0f) < 1e-5f;
    all += 1.0 / drawn->pdf;
    if (glm::dot(drawn->direction, window) > 0.9f) near_window += 1.0 / drawn->pdf;
  }
  // The draws cover the two bins learned, each 4 pi / 128 steradians; the part of them within 0.9 of the window's
  // direction is less than that cap's 2 pi (1 - 0.9).
  EXPECT_GT(double(agree) / n, 0.999);
  EXPECT_NEAR(all / n, 2.0 * 4.0 * kPi / cpu::SkyGuide::kBins, 0.01 * 2.0 * 4.0 * kPi / cpu::SkyGuide::kBins);
  EXPECT_GT(near_window / n, 0.0);
  EXPECT_LT(near_window / n, 2.0 * kPi * 0.1 * 1.01);
  // Learned in the other order, the same densities.
  cpu::SkyGuide reversed(glm::vec3(0.0f), glm::vec3(4.0f, 4.0f, 2.0f));
  for (int i = 0; i < 50; ++i) reversed.learn(1, x, up, 0.1f);
  for (int i = 0; i < 300; ++i) reversed.learn(1, x, window, 0.5f);
  reversed.update();
  EXPECT_EQ(reversed.pdf(0, x, window), guide.pdf(0, x, window));
  EXPECT_EQ(reversed.pdf(0, x, up), guide.pdf(0, x, up));
}

TEST(TileMatrix, MapsTheTileOntoTheWholeClipSquare) {
  // Tile (64..128) x (0..32) of a 256 x 128 image: its corners must land on clip -1 and +1.
  const glm::mat4 m = tile_matrix(256, 128, 64, 0, 64, 32, glm::vec2(0.0f));
  const glm::vec4 lower = m * glm::vec4(2.0f * 64 / 256 - 1, 2.0f * 0 / 128 - 1, 0, 1);
  const glm::vec4 upper = m * glm::vec4(2.0f * 128 / 256 - 1, 2.0f * 32 / 128 - 1, 0, 1);
  EXPECT_NEAR(lower.x, -1.0f, 1e-6f);
  EXPECT_NEAR(lower.y, -1.0f, 1e-6f);
  EXPECT_NEAR(upper.x, 1.0f, 1e-6f);
  EXPECT_NEAR(upper.y, 1.0f, 1e-6f);
  // A jitter of one pixel moves the image by 2 / width in clip space.
  const glm::mat4 j = tile_matrix(256, 128, 0, 0, 256, 128, glm::vec2(1.0f, 0.0f));
  EXPECT_NEAR((j * glm::vec4(0, 0, 0, 1)).x, 2.0f / 256, 1e-7f);
}

}  // namespace
}  // namespace bounce
