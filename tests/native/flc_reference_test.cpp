// The CPU reference of the Forward Light Cuts target (native/reference) against closed forms, and its Embree
// shim against brute force. Paper: Laurent et al. 2016, Sec. 5, Eq. 4-6.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "embree/embree_device.h"
#include "reference/flc_reference.h"

namespace bounce::reference {
namespace {

constexpr double kPi = 3.14159265358979323846;

BounceLight make_light(int type, glm::vec3 position, glm::vec3 intensity, glm::vec3 axis_z = {0, 0, 1}) {
  BounceLight light{};
  light.type = type;
  light.cast_shadow = 1;
  std::memcpy(light.position, &position[0], 12);
  const glm::vec3 z = glm::normalize(axis_z);
  const glm::vec3 x = glm::normalize(glm::cross(std::abs(z.z) < 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0), z));
  const glm::vec3 y = glm::cross(z, x);
  std::memcpy(light.axis_x, &x[0], 12);
  std::memcpy(light.axis_y, &y[0], 12);
  std::memcpy(light.axis_z, &z[0], 12);
  std::memcpy(light.intensity, &intensity[0], 12);
  light.spot_half_angle = float(kPi) / 4;
  return light;
}

// An axis-aligned rectangle as two counter-clockwise triangles around `centre`, spanned by u and v.
void add_quad(std::vector<Triangle>& out, glm::vec3 centre, glm::vec3 u, glm::vec3 v, glm::vec3 albedo) {
  const glm::vec3 a = centre - u - v, b = centre + u - v, c = centre + u + v, d = centre - u + v;
  out.push_back({{a, b, c}, albedo});
  out.push_back({{a, c, d}, albedo});
}

// Icosphere: the icosahedron with each face cut into 4^level, vertices pushed onto the sphere. Shared edges
// get bit-identical midpoints, so the soup is watertight.
std::vector<Triangle> icosphere(int level, float radius, glm::vec3 albedo) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  const std::array<glm::vec3, 12> v = {{{-1, t, 0},
                                        {1, t, 0},
                                        {-1, -t, 0},
                                        {1, -t, 0},
                                        {0, -1, t},
                                        {0, 1, t},
                                        {0, -1, -t},
                                        {0, 1, -t},
                                        {t, 0, -1},
                                        {t, 0, 1},
                                        {-t, 0, -1},
                                        {-t, 0, 1}}};
  const int faces[20][3] = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                            {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                            {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  std::vector<std::array<glm::vec3, 3>> tris;
  for (const auto& f : faces)
    tris.push_back({glm::normalize(v[f[0]]), glm::normalize(v[f[1]]), glm::normalize(v[f[2]])});
  for (int l = 0; l < level; ++l) {
    std::vector<std::array<glm::vec3, 3>> next;
    for (const auto& p : tris) {
      const glm::vec3 a = glm::normalize(p[0] + p[1]), b = glm::normalize(p[1] + p[2]), c = glm::normalize(p[2] + p[0]);
      next.push_back({p[0], a, c});
      next.push_back({a, p[1], b});
      next.push_back({c, b, p[2]});
      next.push_back({a, b, c});
    }
    tris = std::move(next);
  }
  std::vector<Triangle> out;
  for (const auto& p : tris) out.push_back({{p[0] * radius, p[1] * radius, p[2] * radius}, albedo});
  return out;
}

glm::vec3 centroid(const Triangle& t) { return (t.p[0] + t.p[1] + t.p[2]) / 3.0f; }
glm::vec3 normal(const Triangle& t) { return glm::normalize(glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0])); }

double relative_error(double got, double expected) { return std::abs(got - expected) / std::abs(expected); }

// ---- 1. Furnace -------------------------------------------------------------------------------------------

// A point light of intensity I at the centre of a closed sphere of radius R, albedo rho. On the sphere
// cos_x = cos_y = d / 2R, so Eq. 4-6 integrate to rho * (rho E0) / pi, E0 = I / R^2 (the cosine lobe of Eq. 6
// is exact in expectation here). The icosphere's flat faces lie inside the sphere, up to delta closer to the
// centre than R: E = I cos / r^2 grows and the transfer kernel changes by O(delta / R). Measured over levels 2
// to 6, the bias is +1.5 delta / R (continuous) and +2.2 delta / R (many lights), a quarter per level; the tests
// allow 3 delta / R plus 0.1 % of Monte Carlo error, and choose levels where that stays under 1 %.
class FlcReferenceFurnace : public ::testing::Test {
 protected:
  static constexpr float kRadius = 2.0f, kIntensity = 10.0f, kAlbedo = 0.8f;
  static double expected() { return kAlbedo * kAlbedo * (kIntensity / (kRadius * kRadius)) / kPi; }

  static Scene make_scene(int level) {
    return Scene(icosphere(level, kRadius, glm::vec3(kAlbedo)),
                 {make_light(BOUNCE_LIGHT_POINT, glm::vec3(0.0f), glm::vec3(kIntensity))});
  }
  // Worst gap between a face and the sphere, relative to R: the face's plane distance is smallest at its centroid.
  static double tessellation_gap(const Scene& scene) {
    double gap = 0.0;
    for (const Triangle& t : scene.triangles()) {
      gap = std::max(gap, 1.0 - std::abs(double(glm::dot(normal(t), t.p[0]))) / kRadius);
    }
    return gap;
  }
  // Receivers at a few face centroids spread over the sphere, facing the centre.
  static std::vector<Receiver> receivers(const Scene& scene) {
    std::vector<Receiver> out;
    const std::size_t n = scene.triangles().size();
    for (std::size_t i = 0; i < n; i += n / 5) {
      const Triangle& t = scene.triangles()[i];
      const glm::vec3 c = centroid(t), nn = normal(t);
      out.push_back({c, glm::dot(nn, c) > 0.0f ? -nn : nn, glm::vec3(kAlbedo)});
    }
    return out;
  }
};

TEST_F(FlcReferenceFurnace, ContinuousMatchesClosedForm) {
  const Scene scene = make_scene(4);
  const double gap = tessellation_gap(scene);
  ASSERT_LT(3.0 * gap, 0.005) << "tessellation too coarse for a 1 % test";
  Options options;
  options.epsilon = 1e-3f;
  options.points_per_unit_area = 400.0f;
  const std::vector<Receiver> rs = receivers(scene);
  const std::vector<glm::vec3> got = continuous(scene, rs, options);
  double worst = 0.0;
  for (const glm::vec3& l : got) {
    EXPECT_NEAR(l.r, l.g, 1e-6 * l.r);
    worst = std::max(worst, relative_error(l.r, expected()));
  }
  std::printf("furnace continuous: expected %.6f, worst relative error %.3e (3 delta/R = %.3e)\n", expected(), worst,
              3.0 * gap);
  EXPECT_LT(worst, std::min(0.01, 3.0 * gap + 1e-3));
}

TEST_F(FlcReferenceFurnace, ManyLightsMatchesClosedForm) {
  const Scene scene = make_scene(5);
  const double gap = tessellation_gap(scene);
  ASSERT_LT(3.0 * gap, 0.005);
  Options options;
  options.epsilon = 1e-3f;
  const std::vector<glm::vec3> got = many_lights(scene, receivers(scene), options);
  double worst = 0.0;
  for (const glm::vec3& l : got) worst = std::max(worst, relative_error(l.r, expected()));
  std::printf("furnace many lights (%zu VPLs): worst relative error %.3e (3 delta/R = %.3e)\n",
              scene.triangles().size(), worst, 3.0 * gap);
  EXPECT_LT(worst, std::min(0.01, 3.0 * gap + 1e-3));
}

// The whole inside of the sphere seen by a perspective camera at the centre: every pixel hits a wall.
TEST_F(FlcReferenceFurnace, RenderSeesUniformWalls) {
  const Scene scene = make_scene(4);
  const double gap = tessellation_gap(scene);
  BounceCamera camera{};
  const glm::mat4 view = glm::lookAt(glm::vec3(0.0f), glm::vec3(0.3f, 0.2f, -1.0f), glm::vec3(0, 1, 0));
  const glm::mat4 projection = glm::perspective(glm::radians(90.0f), 1.5f, 0.1f, 100.0f);
  std::memcpy(camera.world_to_view, glm::value_ptr(view), 64);
  std::memcpy(camera.projection, glm::value_ptr(projection), 64);
  camera.width = 24;
  camera.height = 16;
  Options options;
  options.epsilon = 1e-3f;
  const Image image = render(scene, camera, Mode::many_lights, options);
  ASSERT_EQ(image.incident.size(), 24u * 16u);
  double worst = 0.0;
  for (std::size_t i = 0; i < image.incident.size(); ++i) {
    EXPECT_EQ(image.covered[i], 1);
    worst = std::max(worst, relative_error(image.radiance(i).r, expected()));
  }
  std::printf("furnace render: worst relative error %.3e over %zu pixels\n", worst, image.incident.size());
  EXPECT_LT(worst, std::min(0.01, 3.0 * gap + 1e-3));
}

// ---- 2. Direct irradiance: visibility and the light formulas --------------------------------------------

// Lambert's formula, as lights.glsl computes it: the projected solid angle of the polygon, clipped to the
// receiver's horizon.
double polygon_irradiance_factor(std::vector<glm::dvec3> polygon, glm::dvec3 x, glm::dvec3 n) {
  for (glm::dvec3& p : polygon) p -= x;
  std::vector<glm::dvec3> clipped;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const glm::dvec3 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
    const double da = glm::dot(n, a), db = glm::dot(n, b);
    if (da >= 0.0) clipped.push_back(a);
    if ((da >= 0.0) != (db >= 0.0)) clipped.push_back(glm::mix(a, b, da / (da - db)));
  }
  if (clipped.size() < 3) return 0.0;
  double sum = 0.0;
  for (std::size_t i = 0; i < clipped.size(); ++i) {
    const glm::dvec3 a = glm::normalize(clipped[i]), b = glm::normalize(clipped[(i + 1) % clipped.size()]);
    const glm::dvec3 c = glm::cross(a, b);
    const double s = glm::length(c);
    sum += glm::dot(n, c) * (s > 1e-12 ? std::atan2(s, glm::dot(a, b)) / s : 1.0);
  }
  return 0.5 * std::abs(sum);
}

std::vector<glm::dvec3> light_outline(const BounceLight& light, int segments = 256) {
  const glm::dvec3 c(light.position[0], light.position[1], light.position[2]);
  const glm::dvec3 u = glm::dvec3(light.axis_x[0], light.axis_x[1], light.axis_x[2]) * double(light.half_size[0]);
  const glm::dvec3 v = glm::dvec3(light.axis_y[0], light.axis_y[1], light.axis_y[2]) * double(light.half_size[1]);
  if (light.type == BOUNCE_LIGHT_AREA_RECT) return {c - u - v, c + u - v, c + u + v, c - u + v};
  std::vector<glm::dvec3> out;  // a fine polygon: the ellipse itself, within 1e-4
  for (int i = 0; i < segments; ++i) {
    const double a = 2.0 * kPi * i / segments;
    out.push_back(c + std::cos(a) * u + std::sin(a) * v);
  }
  return out;
}

TEST(FlcReferenceIrradiance, BlockerCastsShadowOnVpl) {
  std::vector<Triangle> open, blocked;
  add_quad(open, glm::vec3(0.0f), glm::vec3(0.5f, 0, 0), glm::vec3(0, 0.5f, 0), glm::vec3(0.8f));
  blocked = open;
  add_quad(blocked, glm::vec3(0, 0, 1), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0.5f));
  const BounceLight light = make_light(BOUNCE_LIGHT_POINT, {0.1f, 0.2f, 2.0f}, glm::vec3(4.0f));
  Options options;
  for (int blocker = 0; blocker < 2; ++blocker) {
    const Scene scene(blocker ? blocked : open, {light});
    const std::vector<Vpl> vpls = make_vpls(scene, Mode::many_lights, options);
    ASSERT_EQ(vpls.size(), scene.triangles().size());
    for (std::size_t i = 0; i < 2; ++i) {  // the lit square's two triangles
      const Vpl& vpl = vpls[i];
      const glm::vec3 to_light = glm::vec3(0.1f, 0.2f, 2.0f) - vpl.position;
      const float expected = 4.0f * to_light.z / std::pow(glm::length(to_light), 3.0f);
      EXPECT_NEAR(vpl.irradiance_front.g, blocker ? 0.0f : expected, 1e-5f * expected) << "blocker " << blocker;
      EXPECT_EQ(vpl.irradiance_back.g, 0.0f);  // the underside faces away from the light
    }
  }
}

TEST(FlcReferenceIrradiance, SoftAndDirectionalLightsMatchLightsGlsl) {
  std::vector<Triangle> floor;
  add_quad(floor, glm::vec3(0.0f), glm::vec3(3, 0, 0), glm::vec3(0, 3, 0), glm::vec3(0.8f));
  const glm::vec3 y(0.3f, -0.2f, 0.0f), n = glm::normalize(glm::vec3(0.1f, 0.2f, 1.0f));
  Options options;
  options.light_samples = 27;

  // Spot with a soft radius, unblocked: lights.glsl's I cos / (d^2 + r^2) times the smoothstep cone.
  BounceLight spot = make_light(BOUNCE_LIGHT_SPOT, {0.5f, 0.1f, 2.0f}, {2.0f, 3.0f, 4.0f});
  spot.radius = 0.25f;
  spot.spot_half_angle = 0.6f;
  spot.spot_blend = 0.5f;
  spot.spot_cos_falloff = 1;
  const glm::vec3 to_light = glm::vec3(0.5f, 0.1f, 2.0f) - y;
  const float d2 = glm::dot(to_light, to_light);
  const glm::vec3 l = to_light / std::sqrt(d2);
  const float cos_phi = glm::dot(-l, glm::vec3(0, 0, -1));
  const float cos_half = std::cos(0.6f);
  const float t = std::clamp((cos_phi - cos_half) / ((1.0f - cos_half) * 0.5f), 0.0f, 1.0f);
  const float cone = t * t * (3.0f - 2.0f * t) * cos_phi;
  ASSERT_GT(cone, 0.0f);
  const glm::vec3 expected_spot = glm::vec3(2, 3, 4) * glm::dot(n, l) / (d2 + 0.0625f) * cone;
  const glm::vec3 got_spot = irradiance(Scene(floor, {spot}), y, n, options);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got_spot[c], expected_spot[c], 1e-5f * expected_spot[c]);

  // Sun with an angular size, unblocked, then behind a blocker.
  BounceLight sun = make_light(BOUNCE_LIGHT_SUN, glm::vec3(0.0f), glm::vec3(3.0f), {0.2f, 0.1f, 1.0f});
  sun.sun_angle = 0.1f;
  const float expected_sun = 3.0f * glm::dot(n, glm::normalize(glm::vec3(0.2f, 0.1f, 1.0f)));
  EXPECT_NEAR(irradiance(Scene(floor, {sun}), y, n, options).r, expected_sun, 1e-5f * expected_sun);
  std::vector<Triangle> roofed = floor;
  add_quad(roofed, glm::vec3(0, 0, 1), glm::vec3(2, 0, 0), glm::vec3(0, 2, 0), glm::vec3(0.5f));
  EXPECT_EQ(irradiance(Scene(roofed, {sun}), y, n, options).r, 0.0f);
  BounceLight no_shadow = sun;
  no_shadow.cast_shadow = 0;
  EXPECT_NEAR(irradiance(Scene(roofed, {no_shadow}), y, n, options).r, expected_sun, 1e-5f * expected_sun);
}

TEST(FlcReferenceIrradiance, UnblockedAreaLightsMatchPolygonFormula) {
  std::vector<Triangle> floor;
  add_quad(floor, glm::vec3(0.0f), glm::vec3(3, 0, 0), glm::vec3(0, 3, 0), glm::vec3(0.8f));
  const float radiance = 5.0f;
  Options options;
  options.light_samples = 256;
  struct Case {
    int type;
    glm::vec3 axis_z;
    glm::vec3 y, n;
  };
  const Case cases[] = {
      {BOUNCE_LIGHT_AREA_RECT, {0, 0, 1}, {0.3f, -0.2f, 0}, glm::normalize(glm::vec3(0.2f, 0.1f, 1))},
      {BOUNCE_LIGHT_AREA_RECT, {0.3f, 0, 1}, {0.8f, 0.4f, 0}, glm::normalize(glm::vec3(0.3f, -0.1f, 1))},
      // The receiver's horizon cuts the light: the polygon formula clips it.
      {BOUNCE_LIGHT_AREA_RECT, {0, 0, 1}, {0.1f, 0.0f, 0}, glm::normalize(glm::vec3(3.0f, 0.0f, 1))},
      {BOUNCE_LIGHT_AREA_ELLIPSE, {0, 0.2f, 1}, {-0.4f, 0.3f, 0}, glm::normalize(glm::vec3(-0.1f, 0.1f, 1))},
  };
  double worst = 0.0;
  for (const Case& c : cases) {
    BounceLight light = make_light(c.type, {0.0f, 0.0f, 1.5f}, glm::vec3(radiance), c.axis_z);
    light.half_size[0] = 0.5f;
    light.half_size[1] = 0.3f;
    const Scene scene(floor, {light});
    const double expected = radiance * polygon_irradiance_factor(light_outline(light), c.y, c.n);
    ASSERT_GT(expected, 0.0);
    const double got = irradiance(scene, c.y, c.n, options).r;
    worst = std::max(worst, relative_error(got, expected));
    EXPECT_LT(relative_error(got, expected), 0.01) << "type " << c.type << ": " << got << " vs " << expected;
  }
  std::printf("area lights vs polygon formula: worst relative error %.3e\n", worst);
}

// A blocker over the x > 0 half of a light, seen from straight below its centre: by symmetry, half the
// irradiance. The strata of the sample grids (even for the rectangle, a multiple of 4 in azimuth for the ball)
// do not straddle the blocker's edge, so only the jitter inside each stratum is left as error.
TEST(FlcReferenceIrradiance, HalfBlockedLightGivesHalf) {
  std::vector<Triangle> floor;
  add_quad(floor, glm::vec3(0.0f), glm::vec3(3, 0, 0), glm::vec3(0, 3, 0), glm::vec3(0.8f));
  std::vector<Triangle> half = floor;
  add_quad(half, glm::vec3(1.0f, 0, 0.75f), glm::vec3(1, 0, 0), glm::vec3(0, 2, 0), glm::vec3(0.5f));
  BounceLight rect = make_light(BOUNCE_LIGHT_AREA_RECT, {0, 0, 1.5f}, glm::vec3(5.0f));
  rect.half_size[0] = 0.5f;
  rect.half_size[1] = 0.3f;
  BounceLight ball = make_light(BOUNCE_LIGHT_POINT, {0, 0, 1.5f}, glm::vec3(5.0f));
  ball.radius = 0.3f;
  Options options;
  const glm::vec3 y(0.0f), n(0, 0, 1);
  for (const BounceLight& light : {rect, ball}) {
    options.light_samples = light.type == BOUNCE_LIGHT_POINT ? 512 : 256;  // grids of 8^3, 16^2
    const float open = irradiance(Scene(floor, {light}), y, n, options).r;
    const float blocked = irradiance(Scene(half, {light}), y, n, options).r;
    std::printf("half-blocked light type %d: ratio %.5f\n", light.type, blocked / open);
    EXPECT_NEAR(blocked, 0.5f * open, 0.01f * open) << "type " << light.type;
  }
}

// ---- 3. Transfer: Eq. 5 and 6 against closed forms --------------------------------------------------------

// Integral over the rectangle [u0, u1] x [v0, v1] of h^3 / (h^2 + u^2 + v^2)^(5/2): the v integral in closed
// form (antiderivative v (2 v^2 + 3 c^2) / (3 c^4 (c^2 + v^2)^(3/2)), c^2 = h^2 + u^2), the u integral by
// Simpson's rule on a smooth integrand.
double parallel_kernel(double h, double u0, double u1, double v0, double v1) {
  auto inner = [&](double u) {
    const double c2 = h * h + u * u;
    auto f = [&](double v) { return v * (2 * v * v + 3 * c2) / (3 * c2 * c2 * std::pow(c2 + v * v, 1.5)); };
    return h * h * h * (f(v1) - f(v0));
  };
  const int n = 4000;
  const double step = (u1 - u0) / n;
  double sum = inner(u0) + inner(u1);
  for (int i = 1; i < n; ++i) sum += inner(u0 + i * step) * (i % 2 ? 4 : 2);
  return sum * step / 3;
}

// Two parallel facing squares at distance h, the lower one lit by an unshadowed sun from straight above (E
// uniform, its upper side). At x on the upper one, facing down: cos_x = cos_y = h / d, and Eq. 4-6 with the
// paper's cosine lobe give L = rho_e rho_x E 3 / (2 pi^2) * integral of h^3 / d^5 over the lower square.
TEST(FlcReferenceTransfer, ParallelSquaresMatchIntegral) {
  const float half = 1.0f, h = 1.0f, sun = 3.0f, rho_e = 0.7f, rho_x = 0.6f;
  std::vector<Triangle> triangles;
  add_quad(triangles, glm::vec3(0.0f), glm::vec3(half, 0, 0), glm::vec3(0, half, 0), glm::vec3(rho_e));
  add_quad(triangles, glm::vec3(0, 0, h), glm::vec3(half, 0, 0), glm::vec3(0, half, 0), glm::vec3(rho_x));
  BounceLight light = make_light(BOUNCE_LIGHT_SUN, glm::vec3(0.0f), glm::vec3(sun));
  light.cast_shadow = 0;
  const Scene scene(triangles, {light});
  const std::vector<Receiver> receivers = {{{0, 0, h}, {0, 0, -1}, glm::vec3(rho_x)},
                                           {{0.5f, 0.3f, h}, {0, 0, -1}, glm::vec3(rho_x)},
                                           {{-0.9f, 0.8f, h}, {0, 0, -1}, glm::vec3(rho_x)}};
  Options options;
  options.points_per_unit_area = 2000.0f;
  options.cosine_lobe = true;
  const std::vector<glm::vec3> got = continuous(scene, receivers, options);
  double worst = 0.0;
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    const glm::vec3 x = receivers[i].position;
    const double expected = rho_e * rho_x * sun * 3.0 / (2.0 * kPi * kPi) *
                            parallel_kernel(h, -half - x.x, half - x.x, -half - x.y, half - x.y);
    worst = std::max(worst, relative_error(got[i].r, expected));
    EXPECT_LT(relative_error(got[i].r, expected), 0.01) << "receiver " << i << ": " << got[i].r << " vs " << expected;
  }
  std::printf("parallel squares, continuous: worst relative error %.3e\n", worst);

  // The same receivers through render(): an orthographic camera between the squares looking up sees the
  // upper square's underside; rows run bottom to top (image up = world +y here).
  BounceCamera camera{};
  const glm::mat4 view = glm::lookAt(glm::vec3(0, 0, 0.5f), glm::vec3(0, 0, 1), glm::vec3(0, 1, 0));
  const glm::mat4 projection = glm::ortho(-2.0f, 2.0f, -2.0f, 2.0f, 0.01f, 10.0f);
  std::memcpy(camera.world_to_view, glm::value_ptr(view), 64);
  std::memcpy(camera.projection, glm::value_ptr(projection), 64);
  camera.width = camera.height = 8;  // pixel centres at +-0.25, +-0.75, ...: the inner 4 x 4 hit the square
  options.points_per_unit_area = 500.0f;
  const Image image = render(scene, camera, Mode::continuous, options);
  for (int j = 0; j < 8; ++j) {
    for (int i = 0; i < 8; ++i) {
      const bool inside = i >= 2 && i < 6 && j >= 2 && j < 6;
      EXPECT_EQ(image.covered[std::size_t(j) * 8 + std::size_t(i)], inside ? 1 : 0) << i << ", " << j;
      const float value = image.radiance(std::size_t(j) * 8 + std::size_t(i)).r;
      if (!inside) {
        EXPECT_EQ(value, 0.0f) << i << ", " << j;
        continue;
      }
      // Looking up +z with +y up, image right is world -x.
      const double wx = -(-2.0 + (i + 0.5) * 0.5), wy = -2.0 + (j + 0.5) * 0.5;
      const double expected = rho_e * rho_x * sun * 3.0 / (2.0 * kPi * kPi) *
                              parallel_kernel(h, -half - wx, half - wx, -half - wy, half - wy);
      EXPECT_LT(relative_error(value, expected), 0.01) << i << ", " << j << ": " << value << " vs " << expected;
    }
  }
}

// A tiny patch: many_lights is Eq. 5 and the light's radiance (Lambertian, or Eq. 6's lobe) evaluated once at the
// patch centre, times its area, to O((s/d)^2).
TEST(FlcReferenceTransfer, TinyPatchIsOneVpl) {
  const float s = 0.01f, sun = 2.0f, rho_e = 0.5f, rho_x = 0.9f;
  std::vector<Triangle> triangles;
  add_quad(triangles, glm::vec3(0.0f), glm::vec3(s / 2, 0, 0), glm::vec3(0, s / 2, 0), glm::vec3(rho_e));
  const Scene scene(triangles, {make_light(BOUNCE_LIGHT_SUN, glm::vec3(0.0f), glm::vec3(sun))});
  const glm::vec3 x(0.3f, 0.2f, 1.0f), n_x = glm::normalize(glm::vec3(-0.2f, 0.1f, -1.0f));
  const glm::vec3 w = glm::normalize(x);  // y -> x, with y the patch centre
  const double d = glm::length(x);
  const Receiver receiver{x, n_x, glm::vec3(rho_x)};
  for (const bool lobe : {false, true}) {
    const double radiance = lobe ? rho_e * sun * 3.0 / (2.0 * kPi) * w.z : rho_e * sun / kPi;    // Eq. 6
    const double expected = radiance * rho_x * glm::dot(n_x, -w) * w.z / (kPi * d * d) * s * s;  // Eq. 5 * area
    Options options;
    options.cosine_lobe = lobe;
    const double got = many_lights(scene, std::span(&receiver, 1), options)[0].r;
    std::printf("tiny patch (lobe %d), many lights: relative error %.3e\n", int(lobe), relative_error(got, expected));
    EXPECT_LT(relative_error(got, expected), 1e-3) << got << " vs " << expected;
    options.min_points_per_triangle = 400;  // jittered points average the patch's first-order terms out
    const double got_continuous = continuous(scene, std::span(&receiver, 1), options)[0].r;
    std::printf("tiny patch (lobe %d), continuous: relative error %.3e\n", int(lobe),
                relative_error(got_continuous, expected));
    EXPECT_LT(relative_error(got_continuous, expected), 1e-3) << got_continuous << " vs " << expected;
  }
}

// A receiver on a light: d is clamped to epsilon (Eq. 5), so the value is finite and known; exactly on the
// light point the direction is undefined and the light adds nothing.
TEST(FlcReferenceTransfer, EpsilonClampsReceiverOnVpl) {
  const float sun = 2.0f, rho = 0.5f;
  std::vector<Triangle> triangles;
  add_quad(triangles, glm::vec3(0.0f), glm::vec3(0.5f, 0, 0), glm::vec3(0, 0.5f, 0), glm::vec3(rho));
  const Scene scene(triangles, {make_light(BOUNCE_LIGHT_SUN, glm::vec3(0.0f), glm::vec3(sun))});
  Options options;
  options.epsilon = 0.05f;
  const std::vector<Vpl> vpls = make_vpls(scene, Mode::many_lights, options);
  ASSERT_EQ(vpls.size(), 2u);
  const glm::vec3 y = vpls[0].position;
  // Just above the first light, facing it: cos_x = cos_y = 1, d = epsilon. The second light lies in the plane.
  const Receiver above{y + glm::vec3(0, 0, 1e-5f), {0, 0, -1}, glm::vec3(rho)};
  // Straight along the light's normal the lobe of Eq. 6 is 3 / 2 of a diffuse surface's radiance.
  const double expected = rho * sun / kPi * rho / (kPi * 0.05 * 0.05) * vpls[0].area;
  const glm::vec3 got = gather(vpls, above, options);
  std::printf("receiver on a light: %.6f, clamped closed form %.6f\n", got.r, expected);
  EXPECT_TRUE(std::isfinite(got.r));
  EXPECT_LT(relative_error(got.r, expected), 1e-3) << got.r << " vs " << expected;
  const Receiver on{y, {0, 0, -1}, glm::vec3(rho)};
  const glm::vec3 on_value = gather(vpls, on, options);
  EXPECT_TRUE(std::isfinite(on_value.r));
  EXPECT_GE(on_value.r, 0.0f);
  // Continuous points land anywhere, some within epsilon of the receiver: still finite.
  options.points_per_unit_area = 5000.0f;
  const std::vector<glm::vec3> all = continuous(scene, std::span(&above, 1), options);
  EXPECT_TRUE(std::isfinite(all[0].r));
}

// ---- 4. Embree shim against brute force ------------------------------------------------------------------

struct BruteHit {
  double t;
  uint32_t geometry, prim;
  double u, v;
  double margin;  // how far inside the triangle (smallest barycentric, scaled): small = an edge case
};

std::optional<BruteHit> brute_intersect(const std::vector<std::vector<std::array<glm::dvec3, 3>>>& geometries,
                                        glm::dvec3 o, glm::dvec3 d, double tmin, double tmax,
                                        double* second_t = nullptr) {
  std::optional<BruteHit> best;
  double second = std::numeric_limits<double>::infinity();
  for (uint32_t g = 0; g < geometries.size(); ++g) {
    for (uint32_t i = 0; i < geometries[g].size(); ++i) {
      const auto& p = geometries[g][i];
      const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
      const glm::dvec3 q = glm::cross(d, e2);
      const double det = glm::dot(e1, q);
      if (std::abs(det) < 1e-14) continue;
      const glm::dvec3 s = o - p[0];
      const double u = glm::dot(s, q) / det;
      const glm::dvec3 r = glm::cross(s, e1);
      const double v = glm::dot(d, r) / det;
      const double t = glm::dot(e2, r) / det;
      if (u < 0 || v < 0 || u + v > 1 || t < tmin || t > tmax) continue;
      if (!best || t < best->t) {
        if (best) second = best->t;
        best = BruteHit{t, g, i, u, v, std::min({u, v, 1 - u - v})};
      } else {
        second = std::min(second, t);
      }
    }
  }
  if (second_t) *second_t = second;
  return best;
}

// Whether a ray passes within `margin` (barycentric) of any triangle's edge, or ends within `margin` of one:
// there float and double may disagree legitimately.
bool near_miss(const std::vector<std::vector<std::array<glm::dvec3, 3>>>& geometries, glm::dvec3 o, glm::dvec3 d,
               double tmin, double tmax, double margin) {
  for (const auto& geometry : geometries) {
    for (const auto& p : geometry) {
      const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
      const glm::dvec3 q = glm::cross(d, e2);
      const double det = glm::dot(e1, q);
      if (std::abs(det) < 1e-14) continue;
      const glm::dvec3 s = o - p[0];
      const double u = glm::dot(s, q) / det, v = glm::dot(d, glm::cross(s, e1)) / det;
      const double t = glm::dot(e2, glm::cross(s, e1)) / det;
      const bool inside = u >= -margin && v >= -margin && u + v <= 1 + margin;
      const bool edge = std::min({std::abs(u), std::abs(v), std::abs(1 - u - v)}) < margin;
      const bool end =
          std::abs(t - tmax) < margin * (1 + std::abs(t)) || std::abs(t - tmin) < margin * (1 + std::abs(t));
      if (inside && (edge || end)) return true;
    }
  }
  return false;
}

TEST(EmbreeShim, AgreesWithBruteForce) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  // Two geometries: an indexed mesh (a grid of shared vertices) and a soup of random triangles.
  std::vector<glm::vec3> grid;
  std::vector<std::array<uint32_t, 3>> grid_triangles;
  for (int j = 0; j <= 6; ++j)
    for (int i = 0; i <= 6; ++i) grid.push_back({-1.5f + 0.5f * i, -1.5f + 0.5f * j, 0.2f * unit(rng)});
  for (uint32_t j = 0; j < 6; ++j) {
    for (uint32_t i = 0; i < 6; ++i) {
      const uint32_t a = j * 7 + i;
      grid_triangles.push_back({a, a + 1, a + 8});
      grid_triangles.push_back({a, a + 8, a + 7});
    }
  }
  std::vector<glm::vec3> soup;
  for (int i = 0; i < 150; ++i) {
    const glm::vec3 c(unit(rng), unit(rng), unit(rng));
    for (int k = 0; k < 3; ++k) soup.push_back(c + 0.3f * glm::vec3(unit(rng), unit(rng), unit(rng)));
  }
  embree::Scene scene;
  EXPECT_EQ(scene.add_triangles(grid, grid_triangles), 0u);
  EXPECT_EQ(scene.add_triangles(soup), 1u);
  scene.commit();
  ASSERT_EQ(scene.triangle_count(0), grid_triangles.size());
  ASSERT_EQ(scene.triangle_count(1), soup.size() / 3);

  std::vector<std::vector<std::array<glm::dvec3, 3>>> geometries(2);
  for (uint32_t g = 0; g < 2; ++g) {
    for (uint32_t i = 0; i < scene.triangle_count(g); ++i) {
      const auto p = scene.triangle(g, i);
      geometries[g].push_back({glm::dvec3(p[0]), glm::dvec3(p[1]), glm::dvec3(p[2])});
    }
  }
  int hits = 0, compared = 0, occluded_rays = 0;
  for (int r = 0; r < 3000; ++r) {
    const glm::vec3 o = 2.0f * glm::vec3(unit(rng), unit(rng), unit(rng));
    const glm::vec3 target = 0.8f * glm::vec3(unit(rng), unit(rng), unit(rng));
    const glm::vec3 d = (target - o) * (0.5f + 0.5f * (unit(rng) + 1.0f));  // not unit length
    const float tmin = r % 3 == 0 ? 0.2f : 0.0f;
    const float tmax = r % 4 == 0 ? 0.6f + unit(rng) * 0.3f : std::numeric_limits<float>::infinity();
    if (near_miss(geometries, o, d, tmin, tmax, 1e-4)) continue;
    ++compared;
    double second = 0.0;
    const auto expected = brute_intersect(geometries, o, d, tmin, tmax, &second);
    const auto got = scene.intersect(o, d, tmin, tmax);
    ASSERT_EQ(got.has_value(), expected.has_value()) << "ray " << r;
    EXPECT_EQ(scene.occluded(o, d, tmin, tmax), expected.has_value()) << "ray " << r;
    if (!expected) continue;
    ++hits;
    occluded_rays += scene.occluded(o, d, tmin, tmax);
    EXPECT_NEAR(got->t, expected->t, 1e-4 * (1.0 + expected->t)) << "ray " << r;
    if (second - expected->t < 1e-4 * (1.0 + expected->t)) continue;  // two hits at one t: either is right
    ASSERT_EQ(got->geometry_id, expected->geometry) << "ray " << r;
    ASSERT_EQ(got->prim_id, expected->prim) << "ray " << r;
    EXPECT_NEAR(got->u, expected->u, 1e-3) << "ray " << r;
    EXPECT_NEAR(got->v, expected->v, 1e-3) << "ray " << r;
    const auto& p = geometries[expected->geometry][expected->prim];
    const glm::dvec3 n = glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));
    EXPECT_NEAR(glm::dot(glm::dvec3(got->normal), n), 1.0, 1e-5) << "ray " << r;
  }
  std::printf("embree shim: %d rays compared, %d hits, %d occluded\n", compared, hits, occluded_rays);
  EXPECT_GT(compared, 2500);
  EXPECT_GT(hits, 500);
  EXPECT_LT(hits, compared - 300);
}

// ---- 5. Determinism --------------------------------------------------------------------------------------

TEST(FlcReferenceDeterminism, SameSeedSameResult) {
  std::vector<Triangle> triangles;
  add_quad(triangles, glm::vec3(0.0f), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0.8f));
  add_quad(triangles, glm::vec3(0, 0, 1.2f), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0.6f, 0.5f, 0.4f));
  add_quad(triangles, glm::vec3(0.2f, 0.1f, 0.5f), glm::vec3(0.2f, 0, 0), glm::vec3(0, 0.2f, 0), glm::vec3(0.3f));
  BounceLight area = make_light(BOUNCE_LIGHT_AREA_RECT, {0, 0, 1.1f}, glm::vec3(4.0f));
  area.half_size[0] = area.half_size[1] = 0.3f;
  BounceLight ball = make_light(BOUNCE_LIGHT_POINT, {0.5f, -0.3f, 0.8f}, glm::vec3(1.0f));
  ball.radius = 0.2f;
  const Scene scene(triangles, {area, ball});
  BounceCamera camera{};
  const glm::mat4 view = glm::lookAt(glm::vec3(0, -0.9f, 0.6f), glm::vec3(0, 0, 0.3f), glm::vec3(0, 0, 1));
  const glm::mat4 projection = glm::perspective(1.2f, 1.0f, 0.05f, 20.0f);
  std::memcpy(camera.world_to_view, glm::value_ptr(view), 64);
  std::memcpy(camera.projection, glm::value_ptr(projection), 64);
  camera.width = camera.height = 12;
  Options options;
  options.seed = 42;
  options.points_per_unit_area = 50.0f;
  options.light_samples = 8;
  options.threads = 2;
  auto bits = [](const Image& image) {
    std::vector<uint32_t> out(image.incident.size() * 3);
    std::memcpy(out.data(), image.incident.data(), out.size() * 4);
    return out;
  };
  const auto a = bits(render(scene, camera, Mode::continuous, options));
  const auto b = bits(render(scene, camera, Mode::continuous, options));
  options.threads = 1;
  const auto c = bits(render(scene, camera, Mode::continuous, options));
  EXPECT_EQ(a, b);
  EXPECT_EQ(a, c);  // the thread count does not matter either
  options.seed = 43;
  const auto d = bits(render(scene, camera, Mode::continuous, options));
  EXPECT_NE(a, d);
  EXPECT_GT(std::count_if(a.begin(), a.end(), [](uint32_t v) { return v != 0; }), 100);
}

}  // namespace
}  // namespace bounce::reference
