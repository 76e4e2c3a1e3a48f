// Forward Light Cuts is unbiased (paper Eq. 8-11): the mean of M independent frames approaches the many-light
// sum L^ML of Eq. 4, computed by brute force on the CPU (native/reference), with an error falling as
// 1/sqrt(M). On a Cornell box meshed finely enough that no triangle is divergent, with VPLs at the triangle
// centroids (no jitter), one pixel per receiver (no interleaving) and no blur, FLC's expectation is exactly
// L^ML; interleaving and blur then add a bias of their own, measured on its own.
#include <gtest/gtest.h>

#include <cstdio>

#include "passes/flc/flc_math.h"
#include "reference/flc_reference.h"
#include "render_fixture.h"

namespace bounce::test {
namespace {

struct Quad {
  glm::vec3 corner, u, v;  // corner + s u + t v, s, t in [0, 1]; the side facing cross(u, v) is the front
  glm::vec3 albedo;
};

class FlcUnbiased : public RenderFixture {
 protected:
  // A 1 m Cornell box (red left wall, green right wall, white elsewhere) with two white blocks, each face
  // split into cells of at most `cell` metres, lit by a 0.25 x 0.2 m area light under the ceiling.
  // Without shadows, E(t_i) has the same closed form on both sides, and FLC must match L^ML exactly in
  // expectation; with them, E comes from shadow maps on the GPU and from rays on the CPU.
  void cornell(float cell, bool shadows) {
    const glm::vec3 white(0.73f), red(0.63f, 0.065f, 0.05f), green(0.14f, 0.45f, 0.09f);
    std::vector<Quad> quads = {
        {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, white},  // floor
        {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}, white},  // ceiling
        {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}, white},  // back
        {{0, 0, 0}, {0, 1, 0}, {0, 0, 1}, red},    // left (x = 0)
        {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}, green},  // right (x = 1)
    };
    const auto block = [&](glm::vec3 lo, glm::vec3 size) {
      const glm::vec3 x(size.x, 0, 0), y(0, size.y, 0), z(0, 0, size.z);
      quads.push_back({lo + z, x, y, white});  // top
      quads.push_back({lo, z, x, white});      // front (y = lo.y)
      quads.push_back({lo + y, x, z, white});  // back
      quads.push_back({lo, y, z, white});      // left
      quads.push_back({lo + x, z, y, white});  // right
    };
    block({0.55f, 0.15f, 0.0f}, {0.3f, 0.3f, 0.3f});
    block({0.15f, 0.45f, 0.0f}, {0.3f, 0.3f, 0.6f});

    std::vector<BounceMaterial> materials;
    std::vector<float> matrices;
    std::vector<uint64_t> keys;
    std::vector<uint32_t> offsets, counts, slots;
    for (std::size_t q = 0; q < quads.size(); ++q) {
      const Quad& quad = quads[q];
      const int nu = std::max(1, int(std::ceil(glm::length(quad.u) / cell)));
      const int nv = std::max(1, int(std::ceil(glm::length(quad.v) / cell)));
      std::vector<float> positions;
      std::vector<uint32_t> triangles;
      for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
          const glm::vec3 p = quad.corner + quad.u * (float(i) / nu) + quad.v * (float(j) / nv);
          positions.insert(positions.end(), {p.x, p.y, p.z});
        }
      for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
          const uint32_t a = j * (nu + 1) + i, b = a + 1, c = a + nu + 1, d = c + 1;
          triangles.insert(triangles.end(), {a, b, d, a, d, c});
          for (const auto& t : {std::array<uint32_t, 3>{a, b, d}, std::array<uint32_t, 3>{a, d, c}}) {
            reference::Triangle tri;
            for (int k = 0; k < 3; ++k) tri.p[k] = glm::make_vec3(&positions[3 * t[k]]);
            tri.albedo = quad.albedo;
            triangles_.push_back(tri);
          }
        }
      add_mesh(q + 1, positions, triangles);
      BounceMaterial material{};
      std::memcpy(material.base_color, &quad.albedo[0], 12);
      material.alpha = 1.0f;
      material.alpha_threshold = 0.5f;
      materials.push_back(material);
      keys.push_back(q + 1);
      const glm::mat4 identity(1.0f);
      matrices.insert(matrices.end(), glm::value_ptr(identity), glm::value_ptr(identity) + 16);
      offsets.push_back(static_cast<uint32_t>(q));
      counts.push_back(1);
      slots.push_back(static_cast<uint32_t>(q));
    }
    ASSERT_BOUNCE_OK(bounce_materials_set(engine_, static_cast<uint32_t>(materials.size()), materials.data()));
    const BounceInstancesDesc desc{
        static_cast<uint32_t>(keys.size()),  keys.data(), matrices.data(), offsets.data(), counts.data(),
        static_cast<uint32_t>(slots.size()), slots.data()};
    ASSERT_BOUNCE_OK(bounce_instances_set(engine_, &desc));
    BounceLight light = make_light(BOUNCE_LIGHT_AREA_RECT, {0.5f, 0.5f, 0.999f}, glm::vec3(40.0f));
    light.half_size[0] = 0.125f;
    light.half_size[1] = 0.1f;
    light.cast_shadow = shadows ? 1 : 0;
    lights_ = {light};
    set_lights(lights_);
    set_camera(glm::lookAt(glm::vec3(0.5f, -1.4f, 0.5f), glm::vec3(0.5f, 0.5f, 0.5f), glm::vec3(0, 0, 1)),
               glm::perspective(glm::radians(38.0f), 1.0f, 0.1f, 10.0f), kSize, kSize);
    settings_.method = BOUNCE_METHOD_FLC;
    settings_.flc_visibility = 0;  // the paper's model: L^ML has no indirect visibility
    settings_.filter_width = 0.0f;
    settings_.flc_jitter = 0;
    settings_.flc_tiling = 0;
    settings_.flc_blur_radius = 0;
    settings_.flc_epsilon = 0.05f;
  }

  // The many-light sum with shadows (the light's area sampled by 256 rays per VPL), over cornell()'s scene.
  reference::Image shadowed_reference() const {
    reference::Options options;
    options.epsilon = settings_.flc_epsilon * 0.5f * std::sqrt(3.0f);
    options.light_samples = 256;
    return reference::render(reference::Scene(triangles_, lights_), camera_, reference::Mode::many_lights, options);
  }

  // Pixels away from creases and silhouettes: there the rasterizer's and the ray tracer's pixel centres can
  // land on different faces, which says nothing about the estimator.
  std::vector<bool> inside_faces() {
    const Image normal = read(BOUNCE_AOV_NORMAL);
    std::vector<bool> inside(std::size_t(kSize) * kSize, false);
    for (int y = 1; y + 1 < kSize; ++y)
      for (int x = 1; x + 1 < kSize; ++x) {
        const glm::vec3 n = glm::make_vec3(normal.at(x, y));
        bool same = glm::length(n) > 0.5f;
        for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}})
          same = same && glm::dot(n, glm::make_vec3(normal.at(x + dx, y + dy))) > 0.999f;
        inside[std::size_t(y) * kSize + x] = same;
      }
    return inside;
  }

  // Relative RMSE of the Indirect AOV against `reference` over `mask`.
  static double relative_rmse(const Image& image, const reference::Image& reference, const std::vector<bool>& mask) {
    double error = 0.0, norm = 0.0;
    for (std::size_t i = 0; i < reference.incident.size(); ++i) {
      if (!mask[i]) continue;
      for (int c = 0; c < 3; ++c) {
        const double r = reference.radiance(i)[c], x = image.values[3 * i + c];
        error += (x - r) * (x - r);
        norm += r * r;
      }
    }
    return std::sqrt(error / norm);
  }

  static constexpr int kSize = 48;
  std::vector<reference::Triangle> triangles_;
  std::vector<BounceLight> lights_;
};

TEST_F(FlcUnbiased, MeanOfFramesApproachesTheManyLightSum) {
  cornell(1.0f / 32.0f, false);
  // Regular triangles only: then FLC's expectation is L^ML over these very triangles.
  const float scene_radius = 0.5f * std::sqrt(3.0f);
  const float s0 = 4.0f * kPi * std::pow(settings_.flc_near_distance * scene_radius, 2.0f) /
                   static_cast<float>(settings_.flc_vpls_per_pixel);
  const float largest = 0.5f / (32.0f * 32.0f);
  ASSERT_LT(largest * flc::flc_inverse_cumulative_area(s0, settings_.flc_mu, settings_.flc_levels), 1.0f);

  reference::Options options;
  options.epsilon = settings_.flc_epsilon * scene_radius;
  options.light_samples = 256;
  const reference::Image expected =
      reference::render(reference::Scene(triangles_, lights_), camera_, reference::Mode::many_lights, options);

  std::printf("frames M, relative RMSE against L^ML (CPU), relative RMSE * sqrt(M)\n");
  std::vector<double> rmse;
  std::vector<bool> mask;
  const std::vector<int> frames = {1, 4, 16, 64, 256};
  for (int m : frames) {
    settings_.samples = m;
    const Image indirect = render(BOUNCE_AOV_INDIRECT);
    ASSERT_TRUE(all_finite(indirect));
    if (mask.empty()) mask = inside_faces();
    rmse.push_back(relative_rmse(indirect, expected, mask));
    std::printf("%4d, %.4f, %.3f\n", m, rmse.back(), rmse.back() * std::sqrt(double(m)));
  }
  // Unbiased: the error keeps falling as 1/sqrt(M) (a slope of -1/2 in log-log; the estimate of the slope is
  // itself noisy, the errors of neighbouring pixels being correlated).
  const double slope = std::log(rmse.back() / rmse.front()) / std::log(double(frames.back()));
  std::printf("log-log slope %.3f\n", slope);
  EXPECT_LT(slope, -0.4);
  EXPECT_LT(rmse.back(), 0.015);

  settings_.flc_tiling = 2;
  settings_.flc_blur_radius = 3;
  const double interleaved = relative_rmse(render(BOUNCE_AOV_INDIRECT), expected, mask);
  std::printf("256 frames, tiling 2 and blur 3: %.4f (the bias interleaving and blur add)\n", interleaved);
  EXPECT_LT(interleaved, 0.1);
}

// With shadow maps, E(t_i) comes from them, one unfiltered lookup per VPL and sample toward that sample's point of
// the area light: averaged over the samples, it is the ray-traced soft shadow (0.0097 at 256 frames; 0.028 when
// VPLs used the pixels' filtered lookup).
TEST_F(FlcUnbiased, ShadowMappedIrradianceStaysCloseToRayTraced) {
  cornell(1.0f / 32.0f, true);
  const reference::Image expected = shadowed_reference();
  settings_.shadow_method = BOUNCE_SHADOWS_MAPS;
  settings_.samples = 256;
  const Image indirect = render(BOUNCE_AOV_INDIRECT);
  const double error = relative_rmse(indirect, expected, inside_faces());
  std::printf("256 frames with shadow maps: relative RMSE %.4f\n", error);
  EXPECT_LT(error, 0.02);
}

// With ray-traced shadows the VPLs are lit by rays and four times as many candidates are drawn, each kept with a
// probability in proportion to its light and weighted by its inverse (FlcPass::add_traced_light): the estimate
// stays that of the many lights (0.0081 at 256 frames; 64 here).
TEST_F(FlcUnbiased, LightCandidatesKeptByTheirLightStayUnbiased) {
  cornell(1.0f / 32.0f, true);
  const reference::Image expected = shadowed_reference();
  ASSERT_EQ(settings_.shadow_method, BOUNCE_SHADOWS_RAY_TRACED);
  ASSERT_GT(settings_.flc_vpl_candidates, 1);
  settings_.samples = 64;
  const Image indirect = render(BOUNCE_AOV_INDIRECT);
  const double error = relative_rmse(indirect, expected, inside_faces());
  std::printf("64 frames, VPLs lit by rays, %d candidates each: relative RMSE %.4f\n", settings_.flc_vpl_candidates,
              error);
  EXPECT_LT(error, 0.03);
}

// N_avg (flc_vpls_per_pixel) trades noise for time (Eq. 1): the expectation must not move with it. The faces of
// this Cornell box are single triangles, all divergent: from N_avg ~ 1,000 on, the tessellator's maximum level no
// longer splits them below S-bar_N and Alg. 1's oversize weights carry the rest. Before instancing the divergent
// draw, llvmpipe mangled those triangles and the light grew with N_avg (1.3x at 4,096, 21x from 16,384 on). Fewer
// VPLs are noisier and cheaper: each N_avg gets the samples that bring the noise of the mean to about 0.5 %.
TEST_F(FlcUnbiased, ExpectationDoesNotDependOnVplsPerPixel) {
  cornell(1.0f, false);
  settings_.flc_jitter = 1;  // VPLs anywhere on their part of a triangle: the same bounce however it is split
  settings_.flc_tiling = 2;  // interleaving: 16 times fewer fragments to splat
  camera_.width = camera_.height = 32;
  settings_.flc_vpls_per_pixel = 256;
  settings_.samples = 256;
  const double reference = mean_red(render(BOUNCE_AOV_INDIRECT));
  ASSERT_GT(reference, 0.0);
  std::printf("N_avg, samples, mean Indirect relative to N_avg 256\n");
  for (const auto& [vpls_per_pixel, samples] : {std::pair{16, 4096}, {4096, 16}, {65536, 16}}) {
    settings_.flc_vpls_per_pixel = vpls_per_pixel;
    settings_.samples = samples;
    const double mean = mean_red(render(BOUNCE_AOV_INDIRECT));
    std::printf("%6d, %4d, %.4f\n", vpls_per_pixel, samples, mean / reference);
    EXPECT_NEAR(mean, reference, 0.02 * reference) << "N_avg " << vpls_per_pixel;
  }
}

}  // namespace
}  // namespace bounce::test
