// Analytic checks: a diffuse plane (albedo 0.8) under each light type; the rendered radiance must match the
// closed form L = albedo / pi * E within 1 % (DESIGN.md, light units table).
#include <functional>

#include "render_fixture.h"

namespace bounce::test {
namespace {

constexpr float kAlbedo = 0.8f;
constexpr float kHalf = 4.0f;
constexpr int kSize = 64;

class AnalyticLights : public RenderFixture {
 protected:
  void SetUp() override {
    RenderFixture::SetUp();
    add_plane(1, 40.0f);
    set_instances({1}, {glm::mat4(1.0f)});
    set_albedo(kAlbedo);
    look_down(kHalf, kSize);
  }

  // Compares every pixel whose expected value exceeds 1 % of the peak against `irradiance(x)`.
  void expect_matches(const std::function<float(glm::vec3)>& irradiance, float tolerance = 0.01f) {
    for (int method : {BOUNCE_SHADOWS_MAPS, BOUNCE_SHADOWS_RAY_TRACED})
      for (int shadows = 0; shadows < 2; ++shadows) expect_matches_with(irradiance, tolerance, method, shadows);
  }
  void expect_matches_with(const std::function<float(glm::vec3)>& irradiance, float tolerance, int method,
                           int shadows) {
    {
      settings_.shadow_method = method;
      light_.cast_shadow = shadows;
      set_lights({light_});
      const Image image = render(BOUNCE_AOV_COMBINED);
      ASSERT_TRUE(all_finite(image));
      float peak = 0.0f;
      for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) peak = std::max(peak, irradiance(pixel_world(x, y, kHalf, kSize)));
      ASSERT_GT(peak, 0.0f);
      int compared = 0;
      float worst = 0.0f;
      for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
          const float expected = kAlbedo / kPi * irradiance(pixel_world(x, y, kHalf, kSize));
          if (expected < 0.01f * kAlbedo / kPi * peak) continue;
          const float got = image.at(x, y)[0];
          const float error = std::abs(got - expected) / expected;
          if (error > worst) worst_pixel_ = {x, y, got, expected};
          worst = std::max(worst, error);
          ++compared;
        }
      }
      EXPECT_GT(compared, 100);
      EXPECT_LT(worst, tolerance) << "shadow method " << method << ", shadows " << shadows << ", worst pixel ("
                                  << worst_pixel_.x << ", " << worst_pixel_.y << "): " << worst_pixel_.got
                                  << " instead of " << worst_pixel_.expected;
    }
  }

  BounceLight light_{};
  struct {
    int x, y;
    float got, expected;
  } worst_pixel_{};
};

TEST_F(AnalyticLights, PointLight) {
  const float power = 1000.0f, height = 3.0f;
  light_ = make_light(BOUNCE_LIGHT_POINT, {0.5f, -0.25f, height}, glm::vec3(power / (4 * kPi)));
  expect_matches([&](glm::vec3 p) {
    const glm::vec3 d = glm::vec3(0.5f, -0.25f, height) - p;
    const float d2 = glm::dot(d, d);
    return power / (4 * kPi) * (d.z / std::sqrt(d2)) / d2;
  });
}

TEST_F(AnalyticLights, PointLightWithRadius) {
  const float power = 500.0f, height = 2.0f, radius = 0.5f;
  light_ = make_light(BOUNCE_LIGHT_POINT, {0, 0, height}, glm::vec3(power / (4 * kPi)));
  light_.radius = radius;
  expect_matches([&](glm::vec3 p) {
    const glm::vec3 d = glm::vec3(0, 0, height) - p;
    const float d2 = glm::dot(d, d);
    return power / (4 * kPi) * (d.z / std::sqrt(d2)) / (d2 + radius * radius);
  });
}

TEST_F(AnalyticLights, SpotLight) {
  const float power = 1000.0f, height = 3.0f, half_angle = 0.6f, blend = 0.3f;
  light_ = make_light(BOUNCE_LIGHT_SPOT, {0, 0, height}, glm::vec3(power / (4 * kPi)));
  light_.spot_half_angle = half_angle;
  light_.spot_blend = blend;
  expect_matches([&](glm::vec3 p) {
    const glm::vec3 d = glm::vec3(0, 0, height) - p;
    const float dist = glm::length(d);
    const float cos_phi = d.z / dist;
    const float cos_half = std::cos(half_angle);
    if (cos_phi <= cos_half) return 0.0f;
    const float t = std::clamp((cos_phi - cos_half) / ((1 - cos_half) * blend), 0.0f, 1.0f);
    return power / (4 * kPi) * t * t * (3 - 2 * t) * cos_phi / (dist * dist);
  });
}

TEST_F(AnalyticLights, SpotLightBlender3CosineFalloff) {
  const float power = 1000.0f, height = 3.0f, half_angle = 0.7f;
  light_ = make_light(BOUNCE_LIGHT_SPOT, {0, 0, height}, glm::vec3(power / (4 * kPi)));
  light_.spot_half_angle = half_angle;
  light_.spot_cos_falloff = 1;
  expect_matches([&](glm::vec3 p) {
    const glm::vec3 d = glm::vec3(0, 0, height) - p;
    const float dist = glm::length(d);
    const float cos_phi = d.z / dist;
    if (cos_phi <= std::cos(half_angle)) return 0.0f;
    return power / (4 * kPi) * cos_phi * cos_phi / (dist * dist);
  });
}

// A nearly hard sun shining toward `towards` (unit), its frame completed around it.
BounceLight make_sun(glm::vec3 towards, float strength) {
  BounceLight light = make_light(BOUNCE_LIGHT_SUN, {0, 0, 10}, glm::vec3(strength));
  const glm::vec3 x =
      glm::normalize(glm::cross(std::abs(towards.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0), towards));
  const glm::vec3 y = glm::cross(towards, x);
  std::memcpy(light.axis_x, &x[0], 12);
  std::memcpy(light.axis_y, &y[0], 12);
  std::memcpy(light.axis_z, &towards[0], 12);
  light.sun_angle = 0.01f;
  return light;
}

TEST_F(AnalyticLights, SunLight) {
  const float strength = 5.0f;
  const glm::vec3 towards = glm::normalize(glm::vec3(0.3f, -0.25f, 1.0f));
  light_ = make_sun(towards, strength);
  expect_matches([&](glm::vec3) { return strength * towards.z; });
}

// Light 80 degrees off the normal: the receiver's own depth in the shadow map changes fastest here, so this is
// where self-shadowing (acne) would show. An unshadowed plane must stay fully lit.
TEST_F(AnalyticLights, SunLightGrazing) {
  const float strength = 5.0f;
  const float angle = 80.0f * kPi / 180.0f;
  light_ = make_sun({std::sin(angle) * 0.8f, std::sin(angle) * 0.6f, std::cos(angle)}, strength);
  expect_matches([&](glm::vec3) { return strength * std::cos(angle); });
}

// A wall of height h at x0 under a sun 1.5 degrees above the horizon shadows the floor up to x0 + h / tan(1.5 deg).
// A shadow ray lifted by d off the floor ends the shadow d / tan(1.5 deg) early: 0.22 m (two pixels here) at the
// old offset of 2e-4 of the scene's radius. Ray-traced shadows, in the direct-light pass and in Topology's.
TEST_F(AnalyticLights, RayTracedShadowEndsWhereTheOccluderSays) {
  const float elevation = 1.5f * kPi / 180.0f, x0 = -3.5f, end = 0.0f;  // end on a pixel boundary
  const float height = (end - x0) * std::tan(elevation);
  add_soup(2, {{x0, -20, 0}, {x0, 20, 0}, {x0, 20, height}, {x0, -20, 0}, {x0, 20, height}, {x0, -20, height}});
  set_instances({1, 2}, {glm::mat4(1.0f), glm::mat4(1.0f)});
  light_ = make_sun({-std::cos(elevation), 0.0f, std::sin(elevation)}, 5.0f);
  light_.sun_angle = 0.0f;
  set_lights({light_});
  settings_.shadow_method = BOUNCE_SHADOWS_RAY_TRACED;
  const float lit = kAlbedo / kPi * 5.0f * std::sin(elevation), tolerance = 0.25f * 2 * kHalf / kSize;
  for (int method : {BOUNCE_METHOD_DIRECT, BOUNCE_METHOD_TOPOLOGY}) {
    settings_.method = method;
    const Image image = render(BOUNCE_AOV_DIRECT);
    for (int x = 0; x < kSize; ++x) {
      const float px = pixel_world(x, kSize / 2, kHalf, kSize).x, got = image.at(x, kSize / 2)[0];
      if (px > x0 && px < end - tolerance) {
        EXPECT_LT(got, 0.01f * lit) << "method " << method << ": pixel " << x << " (x = " << px << ") is lit";
      } else if (px > end + tolerance) {
        EXPECT_NEAR(got, lit, 0.01f * lit) << "method " << method << ": pixel " << x << " (x = " << px << ")";
      }
    }
  }
}

// A wall's penumbra under a rectangle light, by ray-traced shadows over 16 samples of one ray: each pixel's rays
// take the next points of a rotated R2 sequence every sample (cpu::Progression), so they cover the light evenly.
// A wall of height h in the plane x = 0 hides from the floor point (x > 0, 0) the light's points at height H with
// lx < x (1 - H / h): the visible fraction of a light spanning [-w/2, w/2] falls linearly over the penumbra.
// Independent random points (as before) left a root-mean-square error of 0.101 in that fraction (Topology: 0.104);
// Roberts' R2 sequence 0.078, its 1D projections filling in slowly; Sobol's 0.031.
TEST_F(AnalyticLights, RayTracedPenumbraIsStratifiedOverSamples) {
  const float wall = 1.0f, height = 2.0f, half_width = 1.0f;
  add_soup(2, {{0, -20, 0}, {0, 20, 0}, {0, 20, wall}, {0, -20, 0}, {0, 20, wall}, {0, -20, wall}});
  set_instances({1, 2}, {glm::mat4(1.0f), glm::mat4(1.0f)});
  light_ = make_light(BOUNCE_LIGHT_AREA_RECT, {0.0f, 0.0f, height}, glm::vec3(10.0f));
  light_.half_size[0] = light_.half_size[1] = half_width;
  settings_.shadow_method = BOUNCE_SHADOWS_RAY_TRACED;
  settings_.samples = 16;
  for (int method : {BOUNCE_METHOD_DIRECT, BOUNCE_METHOD_TOPOLOGY}) {
    settings_.method = method;
    light_.cast_shadow = 0;
    set_lights({light_});
    const Image unshadowed = render(BOUNCE_AOV_DIRECT);
    light_.cast_shadow = 1;
    set_lights({light_});
    const Image shadowed = render(BOUNCE_AOV_DIRECT);
    double squared = 0.0, signed_sum = 0.0;
    int compared = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const float px = pixel_world(x, y, kHalf, kSize).x;
        const float visible = (half_width - px * (1.0f - height / wall)) / (2.0f * half_width);
        if (px < 0.1f || visible > 0.95f) continue;
        const double error = shadowed.at(x, y)[0] / unshadowed.at(x, y)[0] - visible;
        squared += error * error;
        signed_sum += error;
        ++compared;
      }
    ASSERT_GT(compared, 300);
    const double rms = std::sqrt(squared / compared), mean = signed_sum / compared;
    EXPECT_LT(rms, 0.05) << "method " << method;
    EXPECT_LT(std::abs(mean), 0.01) << "method " << method;
    std::printf("method %d: %d penumbra pixels, visible fraction's error rms %.4f, mean %.4f\n", method, compared, rms,
                mean);
  }
}

TEST_F(AnalyticLights, PointLightGrazing) {
  const float intensity = 2000.0f;
  const glm::vec3 position(-7.0f, 1.0f, 0.6f);  // low beside the view: 5 to 85 degrees off the normal
  light_ = make_light(BOUNCE_LIGHT_POINT, position, glm::vec3(intensity));
  expect_matches([&](glm::vec3 p) {
    const glm::vec3 d = position - p;
    const float r2 = glm::dot(d, d);
    return intensity * d.z / std::sqrt(r2) / r2;
  });
}

// Irradiance from a Lambertian rectangle by numerical integration (midpoint rule, fine grid): independent of
// the shader's closed form.
float rectangle_irradiance(glm::vec3 p, glm::vec3 centre, glm::vec2 half, float radiance) {
  const int n = 200;
  double sum = 0.0;
  const double dA = (2.0 * half.x / n) * (2.0 * half.y / n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const glm::vec3 q =
          centre + glm::vec3(-half.x + (i + 0.5f) * 2 * half.x / n, -half.y + (j + 0.5f) * 2 * half.y / n, 0);
      const glm::vec3 d = q - p;
      const double r2 = glm::dot(d, d);
      const double cos_receiver = d.z / std::sqrt(r2);
      const double cos_emitter = d.z / std::sqrt(r2);  // emitter faces -z, receiver +z
      if (cos_receiver > 0) sum += cos_receiver * cos_emitter / r2 * dA;
    }
  }
  return static_cast<float>(radiance * sum);
}

TEST_F(AnalyticLights, AreaRectangle) {
  const float radiance = 20.0f;
  const glm::vec3 centre(0.2f, 0.1f, 1.5f);
  light_ = make_light(BOUNCE_LIGHT_AREA_RECT, centre, glm::vec3(radiance));
  light_.half_size[0] = 0.6f;
  light_.half_size[1] = 0.3f;
  expect_matches([&](glm::vec3 p) { return rectangle_irradiance(p, centre, {0.6f, 0.3f}, radiance); });
}

TEST_F(AnalyticLights, AreaDisk) {
  // On the axis of a disk of radius r at height h: E = pi L r^2 / (h^2 + r^2); off axis by numerical
  // integration over the disk.
  const float radiance = 10.0f, r = 0.5f, height = 1.0f;
  light_ = make_light(BOUNCE_LIGHT_AREA_ELLIPSE, {0, 0, height}, glm::vec3(radiance));
  light_.half_size[0] = light_.half_size[1] = r;
  expect_matches(
      [&](glm::vec3 p) {
        const int n = 160;
        double sum = 0.0;
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j) {
            const float qx = -r + (i + 0.5f) * 2 * r / n, qy = -r + (j + 0.5f) * 2 * r / n;
            if (qx * qx + qy * qy > r * r) continue;
            const glm::vec3 d = glm::vec3(qx, qy, height) - p;
            const double r2 = glm::dot(d, d);
            sum += (d.z * d.z / r2) / r2 * (2.0 * r / n) * (2.0 * r / n);
          }
        return static_cast<float>(radiance * sum);
      },
      0.01f);
}

}  // namespace
}  // namespace bounce::test
