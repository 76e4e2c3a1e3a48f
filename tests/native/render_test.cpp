// End-to-end renders through the C API on llvmpipe: determinism, tiling, crops, textures and cut-outs,
// emission, hard inputs, progressive frames, cancellation and several engines at once.
#include <chrono>
#include <ostream>
#include <thread>

#include "noise_estimate.h"
#include "render_fixture.h"

namespace bounce::test {
namespace {

class Render : public RenderFixture {
 protected:
  // A floor, a floating occluder and a sun: a scene with shadows, for comparing renders.
  void build_shadow_scene() {
    add_plane(1, 20.0f);
    add_plane(2, 2.0f);
    set_instances({1, 2}, {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, 0, 1))});
    set_albedo(0.5f);
    BounceLight sun = make_light(BOUNCE_LIGHT_SUN, {0, 0, 10}, glm::vec3(3.0f));
    sun.sun_angle = 0.2f;
    set_lights({sun});
    const glm::mat4 view = glm::lookAt(glm::vec3(0, -6, 4), glm::vec3(0), glm::vec3(0, 0, 1));
    set_camera(view, glm::perspective(0.8f, 1.5f, 0.1f, 100.0f), 96, 64);
  }
};

TEST_F(Render, SameSeedSameImageOtherSeedOtherImage) {
  build_shadow_scene();
  settings_.samples = 4;
  settings_.filter_width = 1.0f;
  settings_.seed = 3;
  const Image a = render();
  const Image b = render();
  EXPECT_EQ(a.values, b.values);
  settings_.seed = 4;
  const Image c = render();
  EXPECT_NE(a.values, c.values);
  camera_.frame = 2;  // the frame number feeds the seed too
  settings_.seed = 3;
  EXPECT_NE(a.values, render().values);
}

TEST_F(Render, TilesAndCropsMatchTheWholeImage) {
  build_shadow_scene();
  const Image whole = render();
  settings_.tile_size = 64;  // 96 x 64 -> two tiles
  const Image tiled = render();
  ASSERT_EQ(tiled.values.size(), whole.values.size());
  // Tiles differ from the whole image only by float rounding in the projection.
  auto close = [](float a, float b) { return std::abs(a - b) <= 1e-3f * std::max(1.0f, std::abs(b)); };
  for (std::size_t i = 0; i < whole.values.size(); ++i) ASSERT_TRUE(close(tiled.values[i], whole.values[i])) << i;
  camera_.crop[0] = 5;  // 85 x 59: two tiles of 43 x 59, the second reaching a pixel past the crop's right edge
  camera_.crop[1] = 3;
  camera_.crop[2] = 90;
  camera_.crop[3] = 62;
  const Image crop = render();
  ASSERT_EQ(crop.width, 85);
  ASSERT_EQ(crop.height, 59);
  for (int y = 0; y < crop.height; ++y)
    for (int x = 0; x < crop.width; ++x)
      for (int c = 0; c < 4; ++c) ASSERT_TRUE(close(crop.at(x, y)[c], whole.at(x + 5, y + 3)[c]));
}

// Tiles share each sample's shadow maps and its VPLs (Forward Light Cuts', and SSVP's with their clusters and
// paraboloid maps): a tiled frame is the untiled one, up to what a tile's own border changes (the interleaving and
// the blur restart at it), and costs little more (printed, not asserted: the machine is noisy).
// Tiles keep their sums on the GPU while the frame's fit in its memory, and take turns with one set of targets
// otherwise (injected: low-gpu-memory); both give the same frame.
struct TiledCase {
  int32_t method;
  bool take_turns;
};
// gtest would print the case's bytes, its padding among them: test names that changed from one listing to the next.
void PrintTo(const TiledCase& c, std::ostream* os) { *os << "method " << c.method << ", take_turns " << c.take_turns; }
class TiledRender : public Render, public ::testing::WithParamInterface<TiledCase> {};
INSTANTIATE_TEST_SUITE_P(Methods, TiledRender,
                         ::testing::Values(TiledCase{BOUNCE_METHOD_FLC, false}, TiledCase{BOUNCE_METHOD_SSVP, false},
                                           TiledCase{BOUNCE_METHOD_FLC, true}, TiledCase{BOUNCE_METHOD_SSVP, true}),
                         [](const auto& info) {
                           return std::string(info.param.method == BOUNCE_METHOD_FLC ? "Flc" : "Ssvp") +
                                  (info.param.take_turns ? "TakingTurns" : "");
                         });

TEST_P(TiledRender, TiledFrameEqualsTheUntiledOne) {
  build_shadow_scene();
  add_plane(3, 4.0f);  // a wall facing the camera, lit by the floor
  set_instances({1, 2, 3},
                {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, 0, 1)),
                 glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0, 2, 2)), kPi / 2, glm::vec3(1, 0, 0))});
  set_camera(glm::lookAt(glm::vec3(0, -6, 4), glm::vec3(0), glm::vec3(0, 0, 1)),
             glm::perspective(0.8f, 151.0f / 96.0f, 0.1f, 100.0f), 151, 96);
  settings_.method = GetParam().method;
  settings_.flc_visibility = 0;
  settings_.samples = 8;
  settings_.filter_width = 1.5f;
  auto seconds = [this] {
    const auto start = std::chrono::steady_clock::now();
    render(BOUNCE_AOV_DIRECT);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  seconds();  // compiles the shaders and builds what a scene keeps
  const double untiled_seconds = seconds();
  const Image direct = read(BOUNCE_AOV_DIRECT), indirect = read(BOUNCE_AOV_INDIRECT);
  settings_.tile_size = 64;  // 3 x 2 tiles of 51 x 48, the last column two pixels past the frame
  if (GetParam().take_turns) setenv("BOUNCE_INJECT_FAULT", "low-gpu-memory", 1);
  seconds();  // allocates the tiles' passes
  const double tiled_seconds = seconds();
  unsetenv("BOUNCE_INJECT_FAULT");
  const Image tiled_direct = read(BOUNCE_AOV_DIRECT), tiled_indirect = read(BOUNCE_AOV_INDIRECT);
  // Direct light: the same but for a few pixels on edges, where the tile's projection rounds differently.
  int differing = 0;
  for (std::size_t i = 0; i < direct.values.size(); ++i)
    differing += std::abs(tiled_direct.values[i] - direct.values[i]) > 1e-3f;
  const double untiled_mean = mean_red(indirect), tiled_mean = mean_red(tiled_indirect);
  std::printf(
      "direct: %d values of %zu differ; indirect: mean %.5f untiled, %.5f tiled; %.2f s untiled, %.2f s "
      "tiled (%.2fx)\n",
      differing, direct.values.size(), untiled_mean, tiled_mean, untiled_seconds, tiled_seconds,
      tiled_seconds / untiled_seconds);
  EXPECT_LE(differing, 12);
  EXPECT_NEAR(mean_red(tiled_direct), mean_red(direct), 1e-3 * mean_red(direct));
  ASSERT_GT(untiled_mean, 0.0);
  EXPECT_NEAR(tiled_mean, untiled_mean, 0.02 * untiled_mean);
}

class RenderShadows : public Render, public ::testing::WithParamInterface<int> {
 protected:
  void SetUp() override {
    Render::SetUp();
    settings_.shadow_method = GetParam();
  }
};
INSTANTIATE_TEST_SUITE_P(Methods, RenderShadows, ::testing::Values(BOUNCE_SHADOWS_MAPS, BOUNCE_SHADOWS_RAY_TRACED),
                         [](const auto& info) { return info.param == BOUNCE_SHADOWS_MAPS ? "Maps" : "Rays"; });

TEST_P(RenderShadows, ShadowOfAnOccluderIsDark) {
  build_shadow_scene();
  settings_.shadow_softness = 0.0f;
  look_down(4, 64);
  const Image image = render(BOUNCE_AOV_DIRECT);
  // Under the occluder (seen from above we see the occluder itself, lit); beside it the floor is lit.
  // Render the floor alone by moving the camera below the occluder's height is not possible from above, so
  // compare the floor's shadow region through the Depth AOV: pixels on the floor (depth 50) next to the
  // occluder along -sun direction are shadowed.
  const Image depth = read(BOUNCE_AOV_DEPTH);
  int shadowed = 0, lit = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      if (std::abs(depth.at(x, y)[0] - 50.0f) > 1e-3f) continue;  // not the floor
      const float v = image.at(x, y)[0];
      (v < 1e-4f ? shadowed : lit) += 1;
    }
  EXPECT_EQ(shadowed, 0) << "the sun is straight above, the occluder hides its own shadow";
  EXPECT_GT(lit, 1000);
}

// An occluder square (side 1, at height 1.5, centred at x = 1) under a light at height 3 straight above the
// origin casts its shadow on the floor over x in [1, 3] (the projection doubles distances). The floor there is
// dark, beside it lit: this pins the shadow maps' orientation for each kind (cube faces included).
TEST_P(RenderShadows, ShadowsFallWhereGeometryPutsThem) {
  add_plane(1, 20.0f);
  add_plane(2, 1.0f);
  set_instances({1, 2}, {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), glm::vec3(1.0f, 0, 1.5f))});
  set_albedo(0.5f);
  settings_.shadow_softness = 0.0f;
  const float half = 4.0f;
  const int size = 64;
  look_down(half, size);
  auto pixel_of = [&](float x, float y) {
    return glm::ivec2(static_cast<int>((x + half) / (2 * half) * size),
                      static_cast<int>((y + half) / (2 * half) * size));
  };
  BounceLight point = make_light(BOUNCE_LIGHT_POINT, {0, 0, 3}, glm::vec3(100.0f));
  BounceLight spot = make_light(BOUNCE_LIGHT_SPOT, {0, 0, 3}, glm::vec3(100.0f));
  spot.spot_half_angle = 1.2f;
  BounceLight area = make_light(BOUNCE_LIGHT_AREA_RECT, {0, 0, 3}, glm::vec3(100.0f / 4e-4f));
  area.half_size[0] = area.half_size[1] = 0.01f;
  // The same small area light with a rotated, scaled and sheared frame (the cube map lives in the light's frame,
  // orthonormalised by the core).
  BounceLight area_rotated = area;
  const float c = std::cos(0.5f), s = std::sin(0.5f);
  const float rotated_x[3] = {2 * c, 2 * s, 0}, rotated_y[3] = {-s + 0.3f * c, c + 0.3f * s, 0};
  std::memcpy(area_rotated.axis_x, rotated_x, 12);
  std::memcpy(area_rotated.axis_y, rotated_y, 12);
  for (const BounceLight& light : {point, spot, area, area_rotated}) {
    set_lights({light});
    const Image image = render(BOUNCE_AOV_DIRECT);
    for (glm::vec2 shadowed : {glm::vec2(1.7f, 0.0f), glm::vec2(2.8f, 0.8f), glm::vec2(2.5f, -0.8f)}) {
      const glm::ivec2 p = pixel_of(shadowed.x, shadowed.y);
      EXPECT_LT(image.at(p.x, p.y)[0], 1e-4f) << "type " << light.type << " at " << shadowed.x << "," << shadowed.y;
    }
    for (glm::vec2 lit :
         {glm::vec2(-1.5f, 0.0f), glm::vec2(2.0f, 1.3f), glm::vec2(0.0f, -2.0f), glm::vec2(3.4f, 0.0f)}) {
      const glm::ivec2 p = pixel_of(lit.x, lit.y);
      EXPECT_GT(image.at(p.x, p.y)[0], 0.01f) << "type " << light.type << " at " << lit.x << "," << lit.y;
    }
  }
  // A sun from 45 degrees towards -x: the shadow is the occluder shifted by 1.5 along +x... i.e. x in [2, 3].
  BounceLight sun = make_light(BOUNCE_LIGHT_SUN, {0, 0, 10}, glm::vec3(1.0f));
  const glm::vec3 towards = glm::normalize(glm::vec3(-1, 0, 1));
  std::memcpy(sun.axis_z, &towards[0], 12);
  const glm::vec3 x = glm::normalize(glm::cross(glm::vec3(0, 1, 0), towards));
  std::memcpy(sun.axis_x, &x[0], 12);
  set_lights({sun});
  const Image image = render(BOUNCE_AOV_DIRECT);
  const glm::ivec2 in_shadow = pixel_of(2.6f, 0.0f), beside = pixel_of(2.6f, 1.0f), before = pixel_of(1.7f, 0.0f);
  EXPECT_LT(image.at(in_shadow.x, in_shadow.y)[0], 1e-4f);
  EXPECT_GT(image.at(beside.x, beside.y)[0], 0.01f);
  EXPECT_GT(image.at(before.x, before.y)[0], 0.01f) << "seen from above this is the occluder, lit";
}

TEST_F(Render, EmissionAndBackground) {
  add_plane(1, 2.0f);
  set_instances({1}, {glm::mat4(1.0f)});
  BounceMaterial emitter{};
  emitter.alpha = 1.0f;
  emitter.alpha_threshold = 0.5f;
  emitter.emission[0] = 3.0f;
  emitter.emission[1] = 2.0f;
  emitter.emission[2] = 1.0f;
  ASSERT_BOUNCE_OK(bounce_materials_set(engine_, 1, &emitter));
  const BounceWorld world{{0.1f, 0.2f, 0.3f}, 0};
  ASSERT_BOUNCE_OK(bounce_world_set(engine_, &world));
  look_down(2, 16);
  const Image image = render();
  EXPECT_FLOAT_EQ(image.at(8, 8)[0], 3.0f);
  EXPECT_FLOAT_EQ(image.at(8, 8)[2], 1.0f);
  EXPECT_FLOAT_EQ(image.at(0, 0)[1], 0.2f);
  EXPECT_FLOAT_EQ(image.at(0, 0)[3], 1.0f);
  const BounceWorld transparent{{0.1f, 0.2f, 0.3f}, 1};
  ASSERT_BOUNCE_OK(bounce_world_set(engine_, &transparent));
  EXPECT_FLOAT_EQ(render().at(0, 0)[3], 0.0f);
}

TEST_F(Render, TextureAndAlphaCutOutInGBufferAndShadows) {
  // An 8x1 texture: the left half red and opaque, the right half transparent. The cut-out half of an occluder
  // must show and light the floor below.
  std::vector<unsigned char> texels;
  for (int i = 0; i < 8; ++i) texels.insert(texels.end(), {255, 0, 0, static_cast<unsigned char>(i < 4 ? 255 : 0)});
  ASSERT_BOUNCE_OK(bounce_texture_set(engine_, 5, 8, 1, BOUNCE_TEXTURE_RGBA8_SRGB, texels.data()));
  const std::vector<float> positions = {-1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1};
  const std::vector<uint32_t> triangles = {0, 1, 2, 0, 2, 3};
  const std::vector<float> uvs = {0, 0, 1, 0, 1, 1, 0, 0, 1, 1, 0, 1};
  BounceMeshDesc mesh{4, positions.data(), 2, triangles.data(), nullptr, uvs.data(), nullptr};
  ASSERT_BOUNCE_OK(bounce_mesh_set(engine_, 2, &mesh));
  add_plane(1, 20.0f);
  const std::vector<uint64_t> keys = {1, 2};
  const glm::mat4 identity(1.0f);
  std::vector<float> matrices;
  for (int i = 0; i < 2; ++i) matrices.insert(matrices.end(), glm::value_ptr(identity), glm::value_ptr(identity) + 16);
  const std::vector<uint32_t> offsets = {0, 1}, counts = {1, 1}, slots = {0, 1};
  const BounceInstancesDesc instances{2, keys.data(), matrices.data(), offsets.data(), counts.data(), 2, slots.data()};
  ASSERT_BOUNCE_OK(bounce_instances_set(engine_, &instances));
  BounceMaterial floor{}, leaf{};
  floor.base_color[0] = floor.base_color[1] = floor.base_color[2] = 0.5f;
  floor.alpha = leaf.alpha = 1.0f;
  floor.alpha_threshold = leaf.alpha_threshold = 0.5f;
  leaf.base_color[0] = leaf.base_color[1] = leaf.base_color[2] = 1.0f;
  leaf.base_color_texture = 5;
  leaf.alpha_from_texture = 1;
  const BounceMaterial materials[2] = {floor, leaf};
  ASSERT_BOUNCE_OK(bounce_materials_set(engine_, 2, materials));
  set_lights({make_light(BOUNCE_LIGHT_SUN, {0, 0, 10}, glm::vec3(1.0f))});
  // From above: pixel 11 sees the opaque red half (u ~ 0.22), pixel 20 the floor through the hole (u ~ 0.78).
  look_down(2, 32);
  const Image albedo = render(BOUNCE_AOV_ALBEDO);
  const Image direct = read(BOUNCE_AOV_DIRECT);
  EXPECT_NEAR(albedo.at(11, 16)[0], 1.0f, 1e-3f);
  EXPECT_NEAR(albedo.at(11, 16)[1], 0.0f, 1e-3f);
  EXPECT_NEAR(albedo.at(20, 16)[0], 0.5f, 1e-3f);
  EXPECT_NEAR(direct.at(20, 16)[0], 0.5f / kPi, 1e-3f) << "the hole must not cast a shadow";
  // Re-sending the lights (the shadow maps are re-rendered) keeps the hole lit.
  set_lights({make_light(BOUNCE_LIGHT_SUN, {0, 0, 10}, glm::vec3(1.0f))});
  const Image floor_only = render(BOUNCE_AOV_DIRECT);
  EXPECT_NEAR(floor_only.at(20, 16)[0], 0.5f / kPi, 1e-3f);
}

TEST_P(RenderShadows, HardInputsGiveFiniteImagesAndCountedDrops) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  add_plane(1, 10.0f);
  add_mesh(2, {0, 0, 1, nan, 0, 1, 0, 1, 1, 1, 1, 1, 2, 2, 1, 3, 3, 1}, {0, 1, 2, 0, 3, 4, 3, 4, 5, 0, 2, 3});
  add_mesh(3, {0, 0, 0, 1, 0, 0}, {});  // no faces
  set_instances({1, 2, 3}, {glm::mat4(1.0f), glm::mat4(1.0f), glm::mat4(1.0f)});
  set_albedo(0.8f);
  BounceLight zero = make_light(BOUNCE_LIGHT_POINT, {0, 0, 2}, glm::vec3(0.0f));
  BounceLight huge = make_light(BOUNCE_LIGHT_POINT, {0, 0, 2}, glm::vec3(1e9f / (4 * kPi)));
  set_lights({zero, huge});
  look_down(5, 32);
  const Image image = render();
  EXPECT_TRUE(all_finite(image));
  BounceSceneStats stats{};
  ASSERT_BOUNCE_OK(bounce_scene_stats(engine_, &stats));
  EXPECT_EQ(stats.dropped_triangles, 3u);  // the NaN triangle and two collinear ones
  EXPECT_EQ(stats.skipped_lights, 1u);
  EXPECT_EQ(stats.light_count, 1u);
  BounceFrameInfo info{};
  ASSERT_BOUNCE_OK(bounce_frame_info(engine_, &info));
  EXPECT_EQ(info.nonfinite_pixels, 0u);
  EXPECT_GT(image.at(12, 16)[0], 1e5f);  // the floor beside the one valid triangle of mesh 2, lit by the huge light
}

TEST_F(Render, EmptySceneRendersTheBackground) {
  const BounceWorld world{{0.25f, 0.25f, 0.25f}, 0};
  ASSERT_BOUNCE_OK(bounce_world_set(engine_, &world));
  set_lights({make_light(BOUNCE_LIGHT_POINT, {0, 0, 2}, glm::vec3(10.0f))});
  look_down(1, 8);
  const Image image = render();
  EXPECT_FLOAT_EQ(image.at(3, 3)[0], 0.25f);
  EXPECT_FLOAT_EQ(read(BOUNCE_AOV_DEPTH).at(3, 3)[0], 1e10f);
}

TEST_F(Render, CameraInsideAClosedBox) {
  // Six faces around the camera, a light inside: every pixel sees a lit wall, nothing is NaN.
  const std::vector<float> p = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1, -1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1};
  add_mesh(1, p, {0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6, 0, 4, 5, 0, 5, 1,
                  1, 5, 6, 1, 6, 2, 2, 6, 7, 2, 7, 3, 3, 7, 4, 3, 4, 0});
  set_instances({1}, {glm::mat4(1.0f)});
  set_albedo(0.8f);
  set_lights({make_light(BOUNCE_LIGHT_POINT, {0.2f, 0.1f, 0.3f}, glm::vec3(10.0f))});
  set_camera(glm::lookAt(glm::vec3(0), glm::vec3(1, 0.2f, 0.1f), glm::vec3(0, 0, 1)),
             glm::perspective(1.2f, 1.0f, 0.01f, 10.0f), 32, 32);
  const Image image = render();
  EXPECT_TRUE(all_finite(image));
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) ASSERT_GT(image.at(x, y)[0], 0.0f) << x << "," << y;
}

TEST_F(Render, OnePixelAndInvalidCameras) {
  build_shadow_scene();
  camera_.width = camera_.height = 1;
  const Image image = render();
  EXPECT_EQ(image.values.size(), 4u);
  EXPECT_TRUE(all_finite(image));
  camera_.width = 0;
  EXPECT_EQ(bounce_render_start(engine_, &settings_, &camera_), BOUNCE_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bounce_last_error()).find("image size 0x1"), std::string::npos);
  camera_.width = 8;
  camera_.crop[2] = 9;
  camera_.crop[3] = 1;
  EXPECT_EQ(bounce_render_start(engine_, &settings_, &camera_), BOUNCE_ERROR_INVALID_ARGUMENT);
  settings_.samples = 0;
  EXPECT_EQ(bounce_render_start(engine_, &settings_, &camera_), BOUNCE_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bounce_last_error()).find("'samples'"), std::string::npos);
}

TEST_P(RenderShadows, ProgressiveFramesAreAveragesOfTheSamples) {
  build_shadow_scene();
  settings_.samples = 8;
  settings_.filter_width = 1.5f;
  const Image final_image = render();
  BounceFrameInfo info{};
  ASSERT_BOUNCE_OK(bounce_frame_info(engine_, &info));
  EXPECT_EQ(info.samples, 8);
  // G-buffer, Shadows, Direct, Compose, Readback; or G-buffer, Direct (ray traced), Compose, Readback
  EXPECT_EQ(info.stage_count, GetParam() == BOUNCE_SHADOWS_MAPS ? 5 : 4);
  EXPECT_STREQ(info.stages[0].name, "G-buffer");
  EXPECT_GT(info.stages[0].gpu_ms, 0.0);
  BounceRenderProgress progress{};
  ASSERT_BOUNCE_OK(bounce_render_progress(engine_, &progress));
  EXPECT_EQ(progress.state, BOUNCE_RENDER_DONE);
  EXPECT_EQ(progress.samples_done, 8);
  EXPECT_GE(progress.frame_serial, 2u) << "a progressive frame after the first sample, then the final one";
  EXPECT_TRUE(all_finite(final_image));
}

TEST_F(Render, CancelStopsARender) {
  build_shadow_scene();
  settings_.samples = 5000;
  ASSERT_BOUNCE_OK(bounce_render_start(engine_, &settings_, &camera_));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_BOUNCE_OK(bounce_render_cancel(engine_));
  EXPECT_EQ(bounce_render_wait(engine_, 10000), BOUNCE_ERROR_CANCELLED);
  settings_.samples = 1;
  EXPECT_TRUE(all_finite(render()));  // the engine is usable afterwards
}

// A GPU method's partial frames hold Combined (a progressive display's AOV: reading every AOV back at each publish
// cost a third of a sample on an H100), and Direct at the noise estimate's checkpoints; the render's last frame
// holds every AOV of its method.
TEST_F(Render, PartialFramesHoldCombinedTheLastFrameEveryAov) {
  build_shadow_scene();
  for (int32_t method : {BOUNCE_METHOD_DIRECT, BOUNCE_METHOD_FLC, BOUNCE_METHOD_SSVP}) {
    SCOPED_TRACE(method);
    settings_.method = method;
    settings_.samples = 5000;
    ASSERT_BOUNCE_OK(bounce_render_start(engine_, &settings_, &camera_));
    BounceFrameInfo partial{};  // this render's first frame (the last render's stays published until then)
    for (const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
         partial.method != method && std::chrono::steady_clock::now() < until;)
      if (bounce_frame_info(engine_, &partial) != BOUNCE_OK || partial.method != method)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ASSERT_BOUNCE_OK(bounce_render_cancel(engine_));
    bounce_render_wait(engine_, -1);
    ASSERT_EQ(partial.method, method) << "no partial frame within a minute";
    EXPECT_EQ(partial.aovs, NoiseEstimate::partial_aovs(partial.samples, 5000));
    EXPECT_TRUE(partial.aovs & (1u << BOUNCE_AOV_COMBINED));
    std::vector<float> albedo(std::size_t(partial.width) * partial.height * 3, -1.0f);
    ASSERT_BOUNCE_OK(bounce_frame_read(engine_, BOUNCE_AOV_ALBEDO, albedo.data(), albedo.size()));
    EXPECT_EQ(*std::max_element(albedo.begin(), albedo.end()), 0.0f) << "an AOV a frame does not hold reads as zeros";

    settings_.samples = 2;
    const Image last = render();
    BounceFrameInfo info{};
    ASSERT_BOUNCE_OK(bounce_frame_info(engine_, &info));
    EXPECT_EQ(info.aovs, bounce_method_aovs(method));
    ASSERT_BOUNCE_OK(bounce_frame_read(engine_, BOUNCE_AOV_ALBEDO, albedo.data(), albedo.size()));
    EXPECT_GT(*std::max_element(albedo.begin(), albedo.end()), 0.0f);
    EXPECT_TRUE(all_finite(last));
  }
}

TEST_F(Render, TwoEnginesAtOnce) {
  build_shadow_scene();
  const Image alone = render();
  BounceEngine* second = nullptr;
  ASSERT_BOUNCE_OK(bounce_engine_create(nullptr, &second));
  std::swap(engine_, second);
  build_shadow_scene();
  settings_.samples = 3;
  ASSERT_BOUNCE_OK(bounce_render_start(engine_, &settings_, &camera_));
  std::swap(engine_, second);
  settings_.samples = 1;
  const Image concurrent = render();
  std::swap(engine_, second);
  EXPECT_EQ(bounce_render_wait(engine_, -1), BOUNCE_OK) << bounce_last_error();
  std::swap(engine_, second);
  bounce_engine_destroy(second);
  EXPECT_EQ(alone.values, concurrent.values);
}

}  // namespace
}  // namespace bounce::test

namespace bounce::test {
namespace {

// Both EGL platforms make a context here (Mesa offers a software EGL device too); a wrong name is refused
// with a message that names the variable.
TEST(EglPlatform, SurfacelessDeviceAndInvalid) {
  for (const char* platform : {"surfaceless", "device"}) {
    BounceEngineDesc desc{platform, 0};
    BounceEngine* engine = nullptr;
    ASSERT_EQ(bounce_engine_create(&desc, &engine), BOUNCE_OK) << platform << ": " << bounce_last_error();
    char info[256];
    ASSERT_EQ(bounce_engine_gl_info(engine, info, sizeof info), BOUNCE_OK);
    EXPECT_NE(std::string(info).find(std::string("EGL ") + platform), std::string::npos) << info;
    EXPECT_NE(std::string(info).find("4."), std::string::npos) << info;
    bounce_engine_destroy(engine);
  }
  BounceEngineDesc bogus{"bogus", 0};
  BounceEngine* engine = nullptr;
  EXPECT_EQ(bounce_engine_create(&bogus, &engine), BOUNCE_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(engine, nullptr);
  EXPECT_NE(std::string(bounce_last_error()).find("BOUNCE_EGL_PLATFORM"), std::string::npos);
}

}  // namespace
}  // namespace bounce::test

namespace bounce::test {
namespace {

// A frame published between bounce_frame_info and bounce_frame_read (here: another size) does not change what
// is read: the read returns the frame the info described.
TEST_F(Render, FrameReadReadsTheDescribedFrame) {
  build_shadow_scene();
  render();
  BounceFrameInfo first{};
  ASSERT_BOUNCE_OK(bounce_frame_info(engine_, &first));
  camera_.width = 40;
  camera_.height = 30;
  ASSERT_BOUNCE_OK(bounce_render_start(engine_, &settings_, &camera_));
  ASSERT_BOUNCE_OK(bounce_render_wait(engine_, -1));
  std::vector<float> pixels(std::size_t(first.width) * first.height * 4);
  EXPECT_EQ(bounce_frame_read(engine_, BOUNCE_AOV_COMBINED, pixels.data(), pixels.size()), BOUNCE_OK)
      << bounce_last_error();
  EXPECT_EQ(read(BOUNCE_AOV_COMBINED).width, 40);
}

}  // namespace
}  // namespace bounce::test
