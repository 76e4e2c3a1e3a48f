// Auto: the scene analysis against closed forms, and the plan it leads to.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "auto_plan.h"
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
  EXPECT_EQ(info.method, BOUNCE_METHOD_TOPOLOGY);
  EXPECT_EQ(info.bounces, 2);
  EXPECT_NE(std::string(info.plan).find("First bounce 33 % and second 26 %"), std::string::npos) << info.plan;
}

// A near-black furnace: each bounce is 2 % of the last, below the 1 % threshold of the image from the second on,
// and the first too at a threshold of 3 %.
TEST_F(AutoPlan, DarkRoomSkipsTheBouncesItDoesNotNeed) {
  build_furnace();
  set_albedo(0.02f);
  BounceFrameInfo info = render_auto();
  EXPECT_EQ(info.method, BOUNCE_METHOD_TOPOLOGY);
  EXPECT_EQ(info.bounces, 1);
  EXPECT_NE(std::string(info.plan).find("Second bounce 0.0 %: skipped (below 1.0 %)"), std::string::npos) << info.plan;
  settings_.auto_threshold = 0.03f;
  info = render_auto();
  EXPECT_EQ(info.method, BOUNCE_METHOD_DIRECT);
  EXPECT_EQ(info.bounces, 0);
  EXPECT_NE(std::string(info.plan).find("Bounces 2.0 %: skipped (below 3.0 %)"), std::string::npos) << info.plan;
  EXPECT_EQ(info.shares.analysis_ms, 0.0f);  // the same scene and view: the analysis is kept
}

// The error a plan accepts is what it leaves out, weighted as relMSE weights it (the benchmarks' measure). In the
// near-black furnace every pixel has the same direct light d, a first bounce of 0.02 d and a second of 0.02 of
// that: a direct-light plan leaves both bounces out, whether Auto chose it or the user did.
TEST_F(AutoPlan, AcceptedErrorIsWhatThePlanLeavesOut) {
  build_furnace();
  set_albedo(0.02f);
  settings_.auto_threshold = 0.03f;
  BounceFrameInfo info = render_auto();
  ASSERT_EQ(info.method, BOUNCE_METHOD_DIRECT);
  const double d = mean_red(read(BOUNCE_AOV_DIRECT)), first = 0.02 * d, second = 0.02 * first;
  const double image = d + first + second;
  const double expected = (first * first + second * second) / (image * image + 0.01);
  EXPECT_GT(expected, 0.0);
  EXPECT_NEAR(info.bias_relmse, expected, expected * 0.05);

  settings_.method = BOUNCE_METHOD_DIRECT;
  settings_.shadow_method = BOUNCE_SHADOWS_RAY_TRACED;
  render();
  ASSERT_BOUNCE_OK(bounce_frame_info(engine_, &info));
  EXPECT_NEAR(info.bias_relmse, expected, expected * 0.05);
  // Shadow maps need no Embree copy of the scene, which is not built for the estimate alone.
  settings_.shadow_method = BOUNCE_SHADOWS_MAPS;
  render();
  ASSERT_BOUNCE_OK(bounce_frame_info(engine_, &info));
  EXPECT_EQ(info.bias_relmse, -1.0f);
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

// An explicit method renders as asked, with no plan; the error it accepts is its bias class on its one bounce and
// the second bounce whole, more without Indirect Shadows than with them.
TEST_F(AutoPlan, ExplicitMethodsHaveNoPlanButTheirBias) {
  build_furnace();
  const BounceFrameInfo auto_info = render_auto();
  ASSERT_EQ(auto_info.method, BOUNCE_METHOD_TOPOLOGY);
  settings_.method = BOUNCE_METHOD_FLC;
  render();
  BounceFrameInfo info{};
  ASSERT_BOUNCE_OK(bounce_frame_info(engine_, &info));
  EXPECT_EQ(info.method, BOUNCE_METHOD_FLC);
  EXPECT_EQ(info.bounces, 1);  // the paper's one, whatever the Bounces setting
  EXPECT_STREQ(info.plan, "");
  EXPECT_EQ(info.shares.direct[0], 0.0f);
  EXPECT_GT(info.bias_relmse, auto_info.bias_relmse);  // the second bounce, a quarter of the image, left out
  const float with_shadows = info.bias_relmse;
  settings_.flc_visibility = 0;
  render();
  ASSERT_BOUNCE_OK(bounce_frame_info(engine_, &info));
  EXPECT_GT(info.bias_relmse, with_shadows);
  // Topology traces its rays whatever the Shadow Method: Embree's copy is always there, and so is the estimate.
  settings_.method = BOUNCE_METHOD_TOPOLOGY;
  settings_.shadow_method = BOUNCE_SHADOWS_MAPS;
  render();
  ASSERT_BOUNCE_OK(bounce_frame_info(engine_, &info));
  EXPECT_GE(info.bias_relmse, 0.0f);
}

// The cost model splits a sample's time by the share of the VPL stages until frames of two VPL counts give a
// line, and scales with the pixels.
TEST(CostModel, SplitsTheSampleTimeAndScalesWithPixels) {
  CostModel costs;
  BounceSettings settings{};
  settings.method = BOUNCE_METHOD_SSVP;
  settings.bounces = 2;
  settings.ssvp_vpls = 250;
  EXPECT_FALSE(costs.predict(BOUNCE_METHOD_SSVP, 2, 1000));
  costs.observe(settings, 1000, 100.0, 0.5);
  const std::optional<SampleCost> cost = costs.predict(BOUNCE_METHOD_SSVP, 2, 2000);
  ASSERT_TRUE(cost);
  EXPECT_NEAR(cost->fixed_ms, 100.0, 1e-9);
  EXPECT_NEAR(cost->per_vpl_ms, 0.4, 1e-9);
  EXPECT_NEAR(cost->at(250), 200.0, 1e-9);
  EXPECT_FALSE(costs.predict(BOUNCE_METHOD_SSVP, 1, 1000));  // one bounce is another plan
  costs.observe(settings, 1000, 200.0, 0.5);                 // the scene got slower: the mean of the last frames
  EXPECT_NEAR(costs.predict(BOUNCE_METHOD_SSVP, 2, 1000)->at(250), 150.0, 1e-9);

  CostModel line;  // frames of two VPL counts: the line through them, whatever the stages said
  line.observe(settings, 1000, 100.0, 0.9);
  settings.ssvp_vpls = 500;
  line.observe(settings, 1000, 150.0, 0.9);
  EXPECT_NEAR(line.predict(BOUNCE_METHOD_SSVP, 2, 1000)->fixed_ms, 50.0, 1e-9);
  EXPECT_NEAR(line.predict(BOUNCE_METHOD_SSVP, 2, 1000)->per_vpl_ms, 0.2, 1e-9);
}

// Kept in a directory, a device's model is written after each frame, and a later process's model of the same
// device reads it and predicts the same costs; another device's, a damaged line or a file of another kind are not
// read as measurements.
TEST(CostModel, KeptForTheNextProcess) {
  const std::filesystem::path directory =
      std::filesystem::temp_directory_path() / ("bounce-cost-model-test-" + std::to_string(::getpid()));
  std::filesystem::remove_all(directory);
  CostModel::keep_in(directory);
  CostModel& kept = CostModel::of_device("test device A");
  BounceSettings settings{};
  settings.method = BOUNCE_METHOD_TOPOLOGY;
  settings.bounces = 1;
  settings.topology_vpls = 256;
  kept.observe(settings, 1000, 50.0, 0.5);
  settings.topology_vpls = 512;
  kept.observe(settings, 1000, 90.0, 0.7);
  // Two engines of the device finishing renders at once (the viewport and F12) leave a whole file.
  auto observe_more = [&kept](BounceSettings other) {
    other.bounces = 2;
    for (int i = 0; i < 20; ++i) kept.observe(other, 1000, 100.0 + i, 0.5);
  };
  std::thread viewport(observe_more, settings), final_render(observe_more, settings);
  viewport.join();
  final_render.join();
  CostModel::keep_in("");
  std::vector<std::filesystem::path> files(std::filesystem::directory_iterator(directory), {});
  ASSERT_EQ(files.size(), 1u);

  CostModel later("test device A"), elsewhere("test device B");
  ASSERT_TRUE(later.read(files[0]));
  EXPECT_EQ(later.frames(), 2u + 8u);  // the two frames with one bounce, the last 8 of 40 with two
  const auto expected = kept.predict(BOUNCE_METHOD_TOPOLOGY, 1, 4000),
             read = later.predict(BOUNCE_METHOD_TOPOLOGY, 1, 4000);
  ASSERT_TRUE(expected && read);
  EXPECT_NEAR(read->fixed_ms, expected->fixed_ms, 1e-9 * expected->at(512));
  EXPECT_NEAR(read->per_vpl_ms, expected->per_vpl_ms, 1e-12);
  EXPECT_FALSE(elsewhere.read(files[0]));
  EXPECT_EQ(elsewhere.frames(), 0u);

  std::ofstream(files[0], std::ios::app) << "4 1 nan 0.5 0.5\n4 1 256 -1 0.5\nnot a line\n";
  CostModel damaged("test device A");
  ASSERT_TRUE(damaged.read(files[0]));
  EXPECT_EQ(damaged.frames(), 10u);
  std::ofstream(files[0], std::ios::trunc) << "something else\ndevice test device A\n4 1 256 0.05 0.5\n";
  EXPECT_FALSE(CostModel("test device A").read(files[0]));
  std::filesystem::remove_all(directory);
}

// A budget buys the VPLs that fill it; below the fixed cost of the second bounce, one bounce; below Topology's
// with one, Screen-Space VPL Propagation and its bounces; below those, direct light, unless the cheapest plan with
// a bounce is nearer the budget (a target, not a ceiling); a plan not measured yet renders as it is.
TEST(CostModel, PlanFitsTheBudget) {
  cpu::SceneAnalysis analysis{};
  analysis.direct[0] = 0.5;
  analysis.first_bounce[0] = 0.3;
  analysis.second_bounce = 0.2;
  BounceSettings settings{};
  settings.method = BOUNCE_METHOD_AUTO;
  settings.auto_threshold = 0.01f;
  settings.bounces = 2;
  settings.samples = 4;
  settings.topology_vpls = 1024;
  settings.sample_budget = 150.0f;
  CostModel costs;
  BounceSettings measured = settings;
  measured.method = BOUNCE_METHOD_TOPOLOGY;
  measured.topology_vpls = 100;
  costs.observe(measured, 1, 120.0, 20.0 / 120.0);  // 100 ms + 0.2 ms per VPL
  auto plan = plan_auto(settings, analysis, costs, 1);
  EXPECT_EQ(plan.settings.method, BOUNCE_METHOD_TOPOLOGY);
  EXPECT_EQ(plan.settings.bounces, 2);
  EXPECT_EQ(plan.settings.topology_vpls, 250);
  EXPECT_NEAR(plan.estimated_ms, 150.0, 1e-6);
  EXPECT_NE(plan.summary.find("Budget 150 ms per sample: 250 VPLs, 150 ms."), std::string::npos) << plan.summary;

  // Below the fewest VPLs the setting offers (64: 112.8 ms), the second bounce goes.
  settings.sample_budget = 90.0f;
  plan = plan_auto(settings, analysis, costs, 1);
  EXPECT_EQ(plan.settings.bounces, 1);
  EXPECT_EQ(plan.settings.method, BOUNCE_METHOD_TOPOLOGY);
  EXPECT_EQ(plan.settings.topology_vpls, 64);  // not measured: the fewest VPLs, the cheapest frame to learn from
  EXPECT_NE(plan.summary.find("second bounce dropped (113 ms), cost not measured yet"), std::string::npos)
      << plan.summary;

  // Topology with one bounce does not fit either: Screen-Space VPL Propagation, measured or not, then direct light.
  measured.bounces = 1;
  costs.observe(measured, 1, 80.0, 20.0 / 80.0);  // 60 ms + 0.2 ms per VPL: 72.8 ms at 64
  settings.sample_budget = 0.0f;
  settings.time_limit = 0.2f;  // 50 ms for each of 4 samples
  plan = plan_auto(settings, analysis, costs, 1);
  EXPECT_EQ(plan.settings.method, BOUNCE_METHOD_SSVP);
  EXPECT_EQ(plan.settings.bounces, 2);
  EXPECT_NE(plan.summary.find("second bounce dropped (113 ms), Topology too slow (73 ms), Screen-Space VPL "
                              "Propagation instead, cost not measured yet"),
            std::string::npos)
      << plan.summary;

  measured.method = BOUNCE_METHOD_SSVP;
  measured.ssvp_vpls = 100;
  for (int bounces : {1, 2}) {
    measured.bounces = bounces;
    costs.observe(measured, 1, 45.0 + 10.0 * bounces, 0.0);  // 55 and 65 ms, whatever the VPLs
  }
  measured.method = BOUNCE_METHOD_DIRECT;
  costs.observe(measured, 1, 40.0, 0.0);
  // 50 ms: one bounce of SSVP (55 ms, 10 % above) is nearer than direct light (40 ms, 25 % below).
  plan = plan_auto(settings, analysis, costs, 1);
  EXPECT_EQ(plan.settings.method, BOUNCE_METHOD_SSVP);
  EXPECT_EQ(plan.settings.bounces, 1);
  EXPECT_EQ(plan.settings.ssvp_vpls, 16);  // the fewest the setting offers
  EXPECT_NEAR(plan.budget_ms, 50.0, 1e-4);
  EXPECT_NEAR(plan.estimated_ms, 55.0, 1e-6);
  EXPECT_NE(plan.summary.find("second bounce dropped (113 ms), Topology too slow (73 ms), Screen-Space VPL "
                              "Propagation instead, second bounce dropped (65 ms), bounces dropped (55 ms), direct "
                              "light 40 ms, nearer the budget: Screen-Space VPL Propagation with one bounce at 16 "
                              "first-bounce VPLs, 55 ms"),
            std::string::npos)
      << plan.summary;
  // 44 ms: direct light (10 % below) is nearer than SSVP (25 % above).
  settings.time_limit = 0.176f;
  plan = plan_auto(settings, analysis, costs, 1);
  EXPECT_EQ(plan.settings.method, BOUNCE_METHOD_DIRECT);
  EXPECT_NE(plan.summary.find("bounces dropped (55 ms), direct light 40 ms."), std::string::npos) << plan.summary;
}

// An effect below the threshold in the image's mean but not pixel by pixel (the root of its error weight) is
// simulated: a second bounce of 0.8 % of the mean that gives 1.6 % pixel by pixel (where the direct light is in
// shadow), and a world of 0.5 % that gives 2 %. Below in both, the same bounce is skipped.
TEST(AutoPlanShares, AnEffectIsSkippedOnlyWhereItIsBelowPixelByPixel) {
  cpu::SceneAnalysis analysis{};
  analysis.direct[0] = 1.0;
  analysis.direct[1] = 0.005;
  analysis.first_bounce[0] = 0.06;
  analysis.second_bounce = 0.009;
  analysis.error_weight_first = 0.01;
  analysis.error_weight_second = 0.016 * 0.016;
  analysis.error_weight_source[1] = 0.02 * 0.02;
  BounceSettings settings{};
  settings.method = BOUNCE_METHOD_AUTO;
  settings.auto_threshold = 0.01f;
  settings.bounces = 2;
  settings.world_lights = 16;
  auto plan = plan_auto(settings, analysis, CostModel{}, 1);
  EXPECT_EQ(plan.settings.method, BOUNCE_METHOD_TOPOLOGY);
  EXPECT_EQ(plan.settings.bounces, 2);
  EXPECT_EQ(plan.settings.world_lights, 16);
  EXPECT_NE(plan.summary.find("Lamps 100 %, world 0.5 % (2.0 % pixel by pixel) of the light. First bounce 5.6 % and "
                              "second 0.8 % (1.6 % pixel by pixel)"),
            std::string::npos)
      << plan.summary;

  analysis.error_weight_second = 0.009 * 0.009;
  analysis.error_weight_source[1] = 0.005 * 0.005;
  plan = plan_auto(settings, analysis, CostModel{}, 1);
  EXPECT_EQ(plan.settings.bounces, 1);
  EXPECT_EQ(plan.settings.world_lights, 0);
  EXPECT_NE(plan.summary.find("Second bounce 0.8 %: skipped (below 1.0 %)"), std::string::npos) << plan.summary;
}

// Through the engine: a frame under a budget is measured (if none of its plan was before), the next fits it.
TEST_F(AutoPlan, SecondFrameFitsTheBudget) {
  build_furnace();
  settings_.sample_budget = 60000.0f;
  BounceFrameInfo info = render_auto();
  EXPECT_NE(std::string(info.plan).find(" Used "), std::string::npos) << info.plan;
  info = render_auto();
  EXPECT_NE(std::string(info.plan).find("8192 VPLs"), std::string::npos) << info.plan;  // the setting's soft maximum
}

// Time Limit: a limit shorter than a sample renders one, in one tile or several, and it is the first sample of a
// longer render (Time Limit applies to every method; Auto also fits its samples into it).
TEST_F(AutoPlan, TimeLimitStopsAfterTheSampleThatSpentIt) {
  // Not the furnace: SSVP's paraboloid draws of its 9,216 triangles run Mesa's tessellator, whose reallocs take
  // over ten minutes under AddressSanitizer.
  build_lit_open_box();
  camera_.width = camera_.height = 96;  // two tiles of 64 a side
  settings_.ssvp_temporal_seeding = 0;  // else each render's k-means starts from the last one's clusters
  for (auto [method, tile_size] : {std::pair{BOUNCE_METHOD_SSVP, 4096}, std::pair{BOUNCE_METHOD_SSVP, 64},
                                   std::pair{BOUNCE_METHOD_TOPOLOGY, 4096}}) {
    settings_.method = method;
    settings_.tile_size = tile_size;
    settings_.samples = 1;
    settings_.time_limit = 0.0f;
    const Image one = render(BOUNCE_AOV_COMBINED);
    settings_.samples = 64;
    settings_.time_limit = 1e-6f;
    const Image limited = render(BOUNCE_AOV_COMBINED);
    BounceFrameInfo info{};
    ASSERT_BOUNCE_OK(bounce_frame_info(engine_, &info));
    EXPECT_EQ(info.samples, 1);
    EXPECT_NEAR(mean_red(limited), mean_red(one), 1e-5 * mean_red(one)) << method << " " << tile_size;
  }
}

}  // namespace
}  // namespace bounce::test
