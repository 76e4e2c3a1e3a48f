// Auto: the scene analysis against closed forms, and the plan it leads to.
#include <gtest/gtest.h>

#include <string>

#include "render_fixture.h"

namespace bounce::test {
namespace {

class AutoPlan : public RenderFixture {
 protected:
  BounceFrameInfo render_auto() {
    settings_.method = BOUNCE_METHOD_AUTO;
    const Image image = render(BOUNCE_AOV_COMBINED);
    EXPECT_TRUE(all_finite(image));
    BounceFrameInfo info{};
    EXPECT_EQ(bounce_frame_info(engine_, &info), BOUNCE_OK);
    return info;
  }
};

// The furnace (a closed sphere of albedo 0.8 round a point light, seen from inside): every bounce adds the albedo
// times the last, so the first bounce is 0.8 of the direct light and the second 0.64 of it, whatever the sphere.
TEST_F(AutoPlan, FurnaceSharesFollowTheAlbedoPowers) {
  build_furnace();
  const BounceFrameInfo info = render_auto();
  const BounceLightShares& s = info.shares;
  EXPECT_NEAR(s.first_bounce[0] / s.direct[0], 0.8, 0.8 * 0.03);
  EXPECT_NEAR(s.second_bounce / s.direct[0], 0.64, 0.64 * 0.05);
  EXPECT_NEAR(s.direct[0] * (1.0 + 0.8 + 0.64), 1.0, 0.03);  // nothing else in view
  EXPECT_EQ(s.direct[1] + s.direct[2] + s.background_seen + s.emission_seen, 0.0f);
  EXPECT_NEAR(s.mean_albedo, 0.8, 1e-3);
  EXPECT_EQ(s.openness, 0.0f);
  EXPECT_GT(s.analysis_ms, 0.0f);
  EXPECT_EQ(info.method, BOUNCE_METHOD_SSVP);
  EXPECT_NE(std::string(info.plan).find("First bounce 33 % and second 26 %"), std::string::npos) << info.plan;
}

// A near-black furnace: each bounce is 2 % of the last, below the 1 % threshold of the image from the second on,
// and the first too at a threshold of 3 %.
TEST_F(AutoPlan, DarkRoomSkipsTheBouncesItDoesNotNeed) {
  build_furnace();
  set_albedo(0.02f);
  BounceFrameInfo info = render_auto();
  EXPECT_EQ(info.method, BOUNCE_METHOD_SSVP);
  EXPECT_NE(std::string(info.plan).find("Second bounce 0.0 %: skipped (below 1.0 %)"), std::string::npos) << info.plan;
  settings_.auto_threshold = 0.03f;
  info = render_auto();
  EXPECT_EQ(info.method, BOUNCE_METHOD_DIRECT);
  EXPECT_NE(std::string(info.plan).find("Bounces 2.0 %: skipped (below 3.0 %)"), std::string::npos) << info.plan;
  EXPECT_EQ(info.shares.analysis_ms, 0.0f);  // the same scene and view: the analysis is kept
}

// A plane alone under a sun: no surface sends light to another, so Auto renders direct light only; the Indirect
// pass it lists is black.
TEST_F(AutoPlan, LonePlaneUnderTheSunIsDirectLight) {
  add_plane(1, 8.0f);
  set_instances({1}, {glm::mat4(1.0f)});
  set_albedo(0.8f);
  set_lights({make_light(BOUNCE_LIGHT_SUN, glm::vec3(0.0f), glm::vec3(3.0f))});
  look_down(2.0f, 16);
  const BounceFrameInfo info = render_auto();
  EXPECT_EQ(info.method, BOUNCE_METHOD_DIRECT);
  EXPECT_NEAR(info.shares.direct[0], 1.0, 1e-6);
  EXPECT_EQ(info.shares.openness, 1.0f);
  const Image indirect = read(BOUNCE_AOV_INDIRECT);
  EXPECT_EQ(mean_red(indirect), 0.0);
  const Image direct = read(BOUNCE_AOV_DIRECT);
  EXPECT_NEAR(mean_red(direct), 0.8 * 3.0 / kPi, 1e-3);
}

// An explicit method renders as asked, with no plan.
TEST_F(AutoPlan, ExplicitMethodsHaveNoPlan) {
  build_furnace();
  settings_.method = BOUNCE_METHOD_FLC;
  render();
  BounceFrameInfo info{};
  ASSERT_BOUNCE_OK(bounce_frame_info(engine_, &info));
  EXPECT_EQ(info.method, BOUNCE_METHOD_FLC);
  EXPECT_STREQ(info.plan, "");
  EXPECT_EQ(info.shares.direct[0], 0.0f);
}

}  // namespace
}  // namespace bounce::test
