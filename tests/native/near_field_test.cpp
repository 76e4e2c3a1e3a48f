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

// A wall's foot on a floor lit from straight above: the wall is lit only by the floor, most of it within a loose
// clamp (0.32 m, a tenth of the scene's radius) of the wall. A tight clamp takes nearly nothing.
class Corner : public RenderFixture {
 protected:
  void SetUp() override {
    RenderFixture::SetUp();
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
  }
  // The wall's `aov` with the method's clamp at `clamp` (a fraction of the scene's radius, 3.2 m).
  double wall_light(float clamp, int aov) {
    settings_.flc_epsilon = settings_.ssvp_distance_clamp = settings_.topology_distance_clamp = clamp;
    const Image image = render(aov);
    EXPECT_TRUE(all_finite(image));
    return mean_red(image);
  }
  // The second bounce with a loose clamp within 8 % of a tight one's.
  void expect_second_bounce_kept(const char* what) {
    const double tight = wall_light(0.002f, BOUNCE_AOV_SECOND_BOUNCE);
    const double loose = wall_light(0.1f, BOUNCE_AOV_SECOND_BOUNCE);
    std::printf("%s, second bounce: clamp 0.002 %.5f, clamp 0.1 %.5f (ratio %.3f)\n", what, tight, loose,
                loose / tight);
    ASSERT_GT(tight, 0.0);
    EXPECT_NEAR(loose / tight, 1.0, 0.08);
  }
};

class NearField : public Corner, public ::testing::WithParamInterface<NearFieldCase> {};

TEST_P(NearField, DistanceClampKeepsTheLightNextToACorner) {
  settings_.method = GetParam().method;
  settings_.shadow_method = GetParam().shadow_method;
  const double tight = wall_light(0.002f, BOUNCE_AOV_INDIRECT), loose = wall_light(0.1f, BOUNCE_AOV_INDIRECT);
  std::printf("wall's foot, first bounce: clamp 0.002 %.5f, clamp 0.1 %.5f (ratio %.3f)\n", tight, loose,
              loose / tight);
  ASSERT_GT(tight, 0.0);
  EXPECT_NEAR(loose / tight, 1.0, 0.05);
}

// The second bounce there, seen from close by, by the methods that have one (SSVP with the traced rays: the
// G-buffer's rays give back the first bounce alone): the floor next to the wall is lit by the wall's first bounce,
// most of it within the loose clamp. The near field gives it back as the first-bounce light gathered where the
// camera sees the surface its ray met, reflected there. Of the tight clamp's second bounce: Topology 0.991, 0.851
// without that (0.93 and 0.575 in a 40-degree view, whose rays meet the wall outside the frame more often); SSVP
// 0.960, 0.815 without.
class NearFieldSecondBounce : public Corner, public ::testing::WithParamInterface<int32_t> {};

TEST_P(NearFieldSecondBounce, DistanceClampKeepsTheSecondBounce) {
  settings_.method = GetParam();
  settings_.shadow_method = BOUNCE_SHADOWS_RAY_TRACED;
  settings_.bounces = 2;
  set_camera(glm::lookAt(glm::vec3(0.5f, 0, 0.3f), glm::vec3(0, 0, 0.05f), glm::vec3(0, 0, 1)),
             glm::perspective(glm::radians(90.0f), 1.0f, 0.05f, 100.0f), 48, 48);
  expect_second_bounce_kept("wall's foot");
}

// The same floor seen from straight above, the wall edge-on and out of the frame: no pixel has the first-bounce
// light of the wall the near field's rays meet. The Topology method estimates it there from a few of the sample's
// VPLs, drawn by the light they give the wall's point, with shadow rays, and a near-field ray from that point (0.830
// of the tight clamp's second bounce without either, 0.911 without the ray).
TEST_F(Corner, TopologyKeepsTheSecondBounceOfWhatTheCameraDoesNotSee) {
  settings_.method = BOUNCE_METHOD_TOPOLOGY;
  settings_.shadow_method = BOUNCE_SHADOWS_RAY_TRACED;
  settings_.bounces = 2;
  set_camera(glm::lookAt(glm::vec3(0.3f, 0, 1.0f), glm::vec3(0.3f, 0, 0), glm::vec3(0, 1, 0)),
             glm::perspective(glm::radians(30.0f), 1.0f, 0.05f, 100.0f), 48, 48);
  expect_second_bounce_kept("floor by the wall from above");
}

// The same in SSVP, whose VPLs are kept by the light they give what the camera sees: the sun leans over the floor
// towards the wall, so that the wall's light gives the floor a first bounce. The wall's first bounce comes from the
// floor's candidates, which light nothing the camera sees. Of the tight clamp's second bounce at 64 samples, seeds
// 0-2: 0.985, 0.990, 0.965; 0.821, 0.821, 0.808 without the estimate.
TEST_F(Corner, SsvpKeepsTheSecondBounceOfWhatTheCameraDoesNotSee) {
  settings_.method = BOUNCE_METHOD_SSVP;
  settings_.shadow_method = BOUNCE_SHADOWS_RAY_TRACED;
  settings_.bounces = 2;
  set_sun({1, 0, 1});
  settings_.samples = 64;  // at 16, seeds 0-2 gave 1.072, 1.033 and 0.970 with the estimate
  set_camera(glm::lookAt(glm::vec3(0.3f, 0, 1.0f), glm::vec3(0.3f, 0, 0), glm::vec3(0, 1, 0)),
             glm::perspective(glm::radians(30.0f), 1.0f, 0.05f, 100.0f), 48, 48);
  expect_second_bounce_kept("floor by the wall from above, sun over the floor");
}

// The Topology method's view, the sun straight above: the floor's candidates light only the wall, so no candidate
// lights what the camera sees and SSVP keeps no first-bounce VPL. The second bounce, traced from the candidates
// onto the wall, still lights the floor (it was black). With a tight clamp, against the Topology method's: 0.992
// at 32 samples (0 before).
TEST_F(Corner, SsvpBouncesTwiceWhereNoFirstBounceReachesTheView) {
  settings_.shadow_method = BOUNCE_SHADOWS_RAY_TRACED;
  settings_.bounces = 2;
  settings_.samples = 32;
  set_camera(glm::lookAt(glm::vec3(0.3f, 0, 1.0f), glm::vec3(0.3f, 0, 0), glm::vec3(0, 1, 0)),
             glm::perspective(glm::radians(30.0f), 1.0f, 0.05f, 100.0f), 48, 48);
  settings_.method = BOUNCE_METHOD_TOPOLOGY;
  const double topology = wall_light(0.002f, BOUNCE_AOV_SECOND_BOUNCE);
  settings_.method = BOUNCE_METHOD_SSVP;
  const double ssvp = wall_light(0.002f, BOUNCE_AOV_SECOND_BOUNCE);
  std::printf("floor by the wall from above, second bounce, clamp 0.002: SSVP %.5f, Topology %.5f (ratio %.3f)\n", ssvp,
              topology, ssvp / topology);
  ASSERT_GT(topology, 0.0);
  EXPECT_NEAR(ssvp / topology, 1.0, 0.1);
  expect_second_bounce_kept("floor by the wall from above, SSVP");
}

INSTANTIATE_TEST_SUITE_P(VplMethods, NearFieldSecondBounce,
                         ::testing::Values(BOUNCE_METHOD_SSVP, BOUNCE_METHOD_TOPOLOGY),
                         [](const ::testing::TestParamInfo<int32_t>& info) {
                           return std::string(info.param == BOUNCE_METHOD_SSVP ? "SsvpRayTraced" : "Topology");
                         });

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
