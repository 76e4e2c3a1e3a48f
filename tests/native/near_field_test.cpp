// The near field (cpu/near_field.h, passes/near_field): what a VPL method's distance clamp takes next to a lit
// surface, given back by Embree rays (the Topology method; FLC and SSVP with ray-traced direct light), or from the
// G-buffer (FLC and SSVP with shadow maps).
#include <gtest/gtest.h>

#include <cstdio>

#include "render_fixture.h"

namespace bounce::test {
namespace {

// A method and where its direct light comes from (the near field follows: Embree rays, or the G-buffer).
struct NearFieldCase {
  int32_t method;
  int32_t shadow_method;
};

class NearField : public RenderFixture, public ::testing::WithParamInterface<NearFieldCase> {
 protected:
  // The wall's first bounce with the method's clamp at `clamp` (a fraction of the scene's radius, 3.2 m).
  double wall_light(float clamp) {
    settings_.flc_epsilon = settings_.ssvp_distance_clamp = settings_.topology_distance_clamp = clamp;
    const Image image = render(BOUNCE_AOV_INDIRECT);
    EXPECT_TRUE(all_finite(image));
    return mean_red(image);
  }
};

// A wall's foot on a floor lit from straight above: the wall is lit only by the floor, most of it within a loose
// clamp (0.32 m) of the wall. A tight clamp takes nearly nothing.
TEST_P(NearField, DistanceClampKeepsTheLightNextToACorner) {
  settings_.method = GetParam().method;
  settings_.shadow_method = GetParam().shadow_method;
  add_mesh(1, {0, -2, 0, 4, -2, 0, 4, 2, 0, 0, 2,  0,   // the floor, x in [0, 4]
               0, -2, 0, 0, 2,  0, 0, 2, 3, 0, -2, 3},  // the wall at x = 0, facing +x
           {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7});
  set_instances({1}, {glm::mat4(1.0f)});
  set_albedo(0.8f);
  set_lights({make_light(BOUNCE_LIGHT_SUN, {0, 0, 10}, glm::vec3(3.0f))});
  // The wall's foot, seen from the floor's far side.
  set_camera(glm::lookAt(glm::vec3(2.5f, 0, 0.4f), glm::vec3(0, 0, 0.15f), glm::vec3(0, 0, 1)),
             glm::perspective(glm::radians(40.0f), 1.0f, 0.05f, 100.0f), 48, 48);
  settings_.samples = 16;
  settings_.flc_visibility = 0;       // nothing to shadow
  settings_.topology_visibility = 1;  // shadow rays: the clamp alone decides
  settings_.topology_resolution = 64;
  settings_.topology_vpls = 2048;
  const double tight = wall_light(0.002f), loose = wall_light(0.1f);
  std::printf("wall's foot, first bounce: clamp 0.002 %.5f, clamp 0.1 %.5f (ratio %.3f)\n", tight, loose,
              loose / tight);
  ASSERT_GT(tight, 0.0);
  EXPECT_NEAR(loose / tight, 1.0, 0.05);
}

INSTANTIATE_TEST_SUITE_P(VplMethods, NearField,
                         ::testing::Values(NearFieldCase{BOUNCE_METHOD_FLC, BOUNCE_SHADOWS_RAY_TRACED},
                                           NearFieldCase{BOUNCE_METHOD_FLC, BOUNCE_SHADOWS_MAPS},
                                           NearFieldCase{BOUNCE_METHOD_SSVP, BOUNCE_SHADOWS_RAY_TRACED},
                                           NearFieldCase{BOUNCE_METHOD_SSVP, BOUNCE_SHADOWS_MAPS},
                                           NearFieldCase{BOUNCE_METHOD_TOPOLOGY, BOUNCE_SHADOWS_RAY_TRACED}),
                         [](const ::testing::TestParamInfo<NearFieldCase>& info) {
                           if (info.param.method == BOUNCE_METHOD_TOPOLOGY) return std::string("Topology");
                           return std::string(info.param.method == BOUNCE_METHOD_FLC ? "ForwardLightCuts" : "Ssvp") +
                                  (info.param.shadow_method == BOUNCE_SHADOWS_RAY_TRACED ? "RayTraced" : "FromGBuffer");
                         });

}  // namespace
}  // namespace bounce::test
