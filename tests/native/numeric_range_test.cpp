// The numeric range policy (native/src/scene_data.cpp) and what it guards: inputs that are finite but beyond what
// float32 rays, shadow maps and depth buffers resolve must never abort, zero the image silently or overflow.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "embree/embree_device.h"
#include "frame.h"
#include "render_fixture.h"

namespace bounce::test {
namespace {

// Debian's Embree keeps its assertions: a ray it cannot take (ray.valid()) would abort the process, so the shim
// answers those itself, as a miss.
TEST(EmbreeShim, RaysEmbreeCannotTakeMissWithoutCallingIt) {
  embree::Scene scene;
  scene.add_triangles(std::vector<glm::vec3>{{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}});
  scene.commit();
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const glm::vec3 above(0, 0, 1), down(0, 0, -1);
  ASSERT_TRUE(scene.intersect(above, down, 0.0f, inf).has_value());
  ASSERT_TRUE(scene.occluded(above, down, 0.0f, inf));
  struct Ray {
    glm::vec3 origin, dir;
    float tmin, tmax;
  };
  for (const Ray& ray :
       {Ray{{nan, 0, 1}, down, 0.0f, inf}, Ray{{0, 0, 1e19f}, down, 0.0f, inf}, Ray{{0, 0, 3e38f}, down, 0.0f, inf},
        Ray{above, {0, 0, -inf}, 0.0f, inf}, Ray{above, {0, 0, -1e19f}, 0.0f, inf},
        Ray{above, {nan, nan, nan}, 0.0f, inf}, Ray{above, down, -1.0f, inf}, Ray{above, down, nan, inf},
        Ray{above, down, 0.0f, nan}, Ray{above, down, 2.0f, 1.0f}}) {
    EXPECT_FALSE(scene.intersect(ray.origin, ray.dir, ray.tmin, ray.tmax).has_value());
    EXPECT_FALSE(scene.occluded(ray.origin, ray.dir, ray.tmin, ray.tmax));
  }
}

// A sliver from a corner 8e8 m out to two corners 7 m apart: in float32 both edges from the far corner round to the
// same vector, their cross product is zero, and the hit's normal was NaN (Topology's cluster view then showed NaN
// pixels, zeroed and counted). Found by the scene fuzzer (fuzz_repros/). Such a hit faces the ray.
TEST(EmbreeShim, SliverFlattenedByFloatFacesTheRay) {
  const glm::dvec3 far(-827339392.0, 883924224.0, -283823136.0), a(2.5, 0.2, -3.7), b(-0.3, 1.2, 3.8);
  embree::Scene scene;
  scene.add_triangles(std::vector<glm::vec3>{glm::vec3(far), glm::vec3(a), glm::vec3(b)});
  scene.commit();
  const glm::dvec3 normal = glm::normalize(glm::cross(a - far, b - far));
  const glm::dvec3 on_sliver = 0.9 * 0.5 * (a + b) + 0.1 * far;
  const glm::vec3 dir(-normal);
  const std::optional<embree::Hit> hit = scene.intersect(glm::vec3(on_sliver + 5.0 * normal), dir, 0.0f, 100.0f);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(glm::length(hit->normal), 1.0f, 1e-5f);
  EXPECT_LT(glm::dot(hit->normal, dir), 0.0f);
}

TEST(FrameNonFinite, EachPixelCountsOnceWhateverItsAovs) {
  Frame frame;
  frame.allocate(4, 2, (1u << BOUNCE_AOV_COMBINED) | (1u << BOUNCE_AOV_DIRECT) | (1u << BOUNCE_AOV_DEPTH));
  for (auto& values : frame.aovs) std::fill(values.begin(), values.end(), 0.5f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  frame.aovs[BOUNCE_AOV_COMBINED][4 * 1 + 2] = nan;  // pixel 1: NaN in every AOV it has
  frame.aovs[BOUNCE_AOV_DIRECT][3 * 1] = nan;
  frame.aovs[BOUNCE_AOV_DEPTH][1] = nan;
  frame.aovs[BOUNCE_AOV_DIRECT][3 * 6 + 1] = std::numeric_limits<float>::infinity();  // pixel 6: in one
  EXPECT_EQ(frame.zero_nonfinite(), 2u);                        // of 8 pixels; 4 non-finite values
  EXPECT_EQ(frame.aovs[BOUNCE_AOV_COMBINED][4 * 1 + 3], 0.0f);  // the whole AOV value of that pixel
  EXPECT_EQ(frame.aovs[BOUNCE_AOV_DIRECT][3 * 6 + 1], 0.0f);
  EXPECT_EQ(frame.aovs[BOUNCE_AOV_COMBINED][4 * 6], 0.5f);  // a finite AOV of the same pixel is kept
  EXPECT_EQ(frame.aovs[BOUNCE_AOV_DEPTH][0], 0.5f);
}

class NumericRange : public RenderFixture {
 protected:
  // A floor, a 1 m square 2 m above it at x = -1 and a light 4 m above the origin: the square's shadow covers
  // x in [-3, -1], y in [-1, 1] of the floor, and the camera looking down sees part of it beside the square.
  void build_floor_and_occluder(const std::vector<uint64_t>& extra_keys = {},
                                const std::vector<glm::mat4>& extra_transforms = {}) {
    add_plane(1, 10.0f);
    add_plane(2, 1.0f);
    std::vector<uint64_t> keys = {1, 2};
    std::vector<glm::mat4> transforms = {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), glm::vec3(-1.0f, 0, 2))};
    keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
    transforms.insert(transforms.end(), extra_transforms.begin(), extra_transforms.end());
    set_instances(keys, transforms);
    set_albedo(0.8f);
    look_down(5, 20);
  }
  BounceSceneStats stats() {
    BounceSceneStats s{};
    EXPECT_EQ(bounce_scene_stats(engine_, &s), BOUNCE_OK) << bounce_last_error();
    return s;
  }
  static constexpr int kLitX = 16, kShadowX = 5, kRow = 10;  // x = 3.25, -2.25; y = 0.25
};

// Geometry 1e20 m away (a triangle of a mesh, an instance moved there) put the shadow maps' far plane at 1e20,
// whose square is no float: hard shadows of point and area lights read as occluded everywhere, and Direct was 0 in
// every method with shadow maps. It is left out now, counted for the report, and the shadows stay right.
TEST_F(NumericRange, FarGeometryIsLeftOutAndShadowsStay) {
  add_soup(3, {{1e20f, 0, 1}, {1e20f, 1, 1}, {1e20f, 0, 2}, {4, 4, 1}, {4.1f, 4, 1}, {4, 4.1f, 1}});
  add_soup(4, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  build_floor_and_occluder({3, 4}, {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), glm::vec3(0, -1e20f, 0))});
  const BounceSceneStats s = stats();
  EXPECT_EQ(s.out_of_range_triangles, 1u);
  EXPECT_EQ(s.out_of_range_instances, 1u);
  EXPECT_EQ(s.triangle_count, 5u);  // the floor's two, the square's two, mesh 3's near one
  EXPECT_LT(s.bounds_max[0], 10.0f);
  EXPECT_GT(s.bounds_min[1], -10.0f);
  BounceLight area = make_light(BOUNCE_LIGHT_AREA_RECT, {0, 0, 4}, glm::vec3(10.0f));
  area.half_size[0] = area.half_size[1] = 0.05f;
  const glm::vec3 to_light = glm::vec3(0, 0, 4) - pixel_world(kLitX, kRow, 5, 20);
  const float cosine = to_light.z / glm::length(to_light), d2 = glm::dot(to_light, to_light);
  const float point_expected = 100.0f * cosine / d2 * 0.8f / kPi;
  const float area_expected = 10.0f * 0.01f * cosine * cosine / d2 * 0.8f / kPi;
  for (const BounceLight& light : {make_light(BOUNCE_LIGHT_POINT, {0, 0, 4}, glm::vec3(100.0f)), area}) {
    set_lights({light});
    settings_.shadow_method = BOUNCE_SHADOWS_MAPS;
    settings_.shadow_softness = 0.0f;
    settings_.topology_resolution = 32;
    settings_.topology_vpls = 64;
    for (int method : {BOUNCE_METHOD_DIRECT, BOUNCE_METHOD_FLC, BOUNCE_METHOD_SSVP, BOUNCE_METHOD_TOPOLOGY}) {
      settings_.method = method;
      const Image direct = render(BOUNCE_AOV_DIRECT);
      ASSERT_TRUE(all_finite(direct));
      const float expected = light.type == BOUNCE_LIGHT_POINT ? point_expected : area_expected;
      EXPECT_NEAR(direct.at(kLitX, kRow)[0], expected, 0.05f * expected)
          << "method " << method << ", light type " << light.type;
      EXPECT_LT(direct.at(kShadowX, kRow)[0], 1e-3f * expected) << "method " << method << ", light type " << light.type;
    }
  }
}

// A point light 1e19 m away sent Topology's VPL paths from there; one of 3e38 W/sr overflowed the sums, and every
// non-finite pixel was zeroed: the whole frame, alpha included. The first is skipped, the second dimmed.
TEST_F(NumericRange, FarAndOverbrightLightsAreSkippedOrDimmed) {
  build_floor_and_occluder();
  const BounceLight far = make_light(BOUNCE_LIGHT_SPOT, {1e19f, 0, 4}, glm::vec3(100.0f));
  const BounceLight overbright = make_light(BOUNCE_LIGHT_POINT, {0, 0, 4}, glm::vec3(3e38f));
  BounceLight sun_far_away = make_light(BOUNCE_LIGHT_SUN, {1e30f, 0, 0}, glm::vec3(1.0f));  // a sun has no position
  sun_far_away.cast_shadow = 0;
  set_lights({far, overbright, sun_far_away});
  const BounceSceneStats s = stats();
  EXPECT_EQ(s.out_of_range_lights, 1u);
  EXPECT_EQ(s.clamped_lights, 1u);
  EXPECT_EQ(s.light_count, 2u);
  for (int method : {BOUNCE_METHOD_TOPOLOGY, BOUNCE_METHOD_DIRECT, BOUNCE_METHOD_FLC, BOUNCE_METHOD_SSVP}) {
    settings_.method = method;
    settings_.topology_resolution = 32;
    settings_.topology_vpls = 64;
    const Image combined = render();
    BounceFrameInfo info{};
    ASSERT_BOUNCE_OK(bounce_frame_info(engine_, &info));
    EXPECT_EQ(info.nonfinite_pixels, 0u) << "method " << method;
    EXPECT_EQ(combined.at(kLitX, kRow)[3], 1.0f) << "method " << method;
    EXPECT_GT(combined.at(kLitX, kRow)[0], 1e12f) << "method " << method;  // 1e15 W/sr at ~5 m
  }
}

// A tilted area light 1 m wide and 2e9 m long (its half size at the range's cap): in float32 its outline, relative
// to a receiver, collapses onto a line through the receiver, and Lambert's formula normalized a zero vector. Every
// pixel the light reached was NaN, zeroed and counted. Found by the scene fuzzer (fuzz_repros/).
TEST_F(NumericRange, AreaLightLongerThanFloatResolvesStaysFinite) {
  build_floor_and_occluder();
  BounceLight strip = make_light(BOUNCE_LIGHT_AREA_RECT, {0, 0, 4}, glm::vec3(10.0f));
  strip.half_size[0] = 0.5f;
  strip.half_size[1] = 1e9f;
  // Tilted, so that the long axis has no zero component left exact.
  const glm::vec3 z = glm::normalize(glm::vec3(0.3f, 0.2f, 1.0f)), x = glm::normalize(glm::cross({0, 1, 0}, z));
  const glm::vec3 y = glm::cross(z, x);
  std::memcpy(strip.axis_x, &x[0], 12);
  std::memcpy(strip.axis_y, &y[0], 12);
  std::memcpy(strip.axis_z, &z[0], 12);
  set_lights({strip});
  settings_.topology_resolution = 32;
  settings_.topology_vpls = 64;
  for (int shadows : {BOUNCE_SHADOWS_MAPS, BOUNCE_SHADOWS_RAY_TRACED}) {
    for (int method : {BOUNCE_METHOD_DIRECT, BOUNCE_METHOD_FLC, BOUNCE_METHOD_SSVP, BOUNCE_METHOD_TOPOLOGY}) {
      settings_.shadow_method = shadows;
      settings_.method = method;
      EXPECT_TRUE(all_finite(render(BOUNCE_AOV_DIRECT))) << "method " << method << ", shadows " << shadows;
      BounceFrameInfo info{};
      ASSERT_BOUNCE_OK(bounce_frame_info(engine_, &info));
      EXPECT_EQ(info.nonfinite_pixels, 0u) << "method " << method << ", shadows " << shadows;
    }
  }
}

// A triangle with corners 1e14 m out, spanning the view 1 m above the floor: its interpolated positions kept so
// little precision that Depth read negative or far off. It is beyond the range: left out, the floor and the square
// show with their own depths.
TEST_F(NumericRange, HugeTriangleBeyondTheRangeLeavesDepthRight) {
  add_soup(3, {{-1e14f, -1e14f, 1}, {1e14f, -1e14f, 1}, {0, 1e14f, 1}});
  build_floor_and_occluder({3}, {glm::mat4(1.0f)});
  set_lights({make_light(BOUNCE_LIGHT_POINT, {0, 0, 4}, glm::vec3(100.0f))});
  const Image depth = render(BOUNCE_AOV_DEPTH);
  EXPECT_EQ(stats().out_of_range_triangles, 1u);
  EXPECT_NEAR(depth.at(kLitX, kRow)[0], 50.0f, 1e-3f);  // the camera is 50 m above the floor
  EXPECT_NEAR(depth.at(8, kRow)[0], 48.0f, 1e-3f);      // and 48 m above the square
}

// Blender's camera matrix for an orthographic scale of 0 is all zeros: the render showed the background only.
TEST_F(NumericRange, SingularProjectionIsRefused) {
  build_floor_and_occluder();
  set_lights({make_light(BOUNCE_LIGHT_POINT, {0, 0, 4}, glm::vec3(100.0f))});
  set_camera(glm::lookAt(glm::vec3(0, 0, 50), glm::vec3(0), glm::vec3(0, 1, 0)), glm::mat4(0.0f), 8, 8);
  EXPECT_EQ(bounce_render_start(engine_, &settings_, &camera_), BOUNCE_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bounce_last_error()).find("singular"), std::string::npos) << bounce_last_error();
}

}  // namespace
}  // namespace bounce::test
