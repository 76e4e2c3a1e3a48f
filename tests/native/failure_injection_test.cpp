// What a machine without EGL, out of GPU memory, or whose Embree cannot start gets: a status and a message that
// says what failed, never a crash, and an engine (or the next one) that renders once the cause is gone.
// BOUNCE_INJECT_FAULT (native/common/fault_injection.h) makes the real failure paths fail.
#include <cstdlib>
#include <string>

#include "render_fixture.h"

namespace bounce::test {
namespace {

class FailureInjection : public RenderFixture {
 protected:
  void TearDown() override {
    unsetenv("BOUNCE_INJECT_FAULT");
    RenderFixture::TearDown();
  }
  static void inject(const char* faults) { setenv("BOUNCE_INJECT_FAULT", faults, 1); }
  static void heal() { unsetenv("BOUNCE_INJECT_FAULT"); }

  void SetUp() override {
    RenderFixture::SetUp();
    const glm::mat4 view = glm::lookAt(glm::vec3(0, -6, 4), glm::vec3(0), glm::vec3(0, 0, 1));
    set_camera(view, glm::perspective(0.8f, 1.5f, 0.1f, 100.0f), 48, 32);
  }
  // A floor, a floating occluder and a sun.
  void build_scene() {
    add_plane(1, 20.0f);
    add_plane(2, 2.0f);
    set_instances({1, 2}, {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, 0, 1))});
    set_albedo(0.5f);
    set_lights({make_light(BOUNCE_LIGHT_SUN, {0, 0, 10}, glm::vec3(3.0f))});
  }
  // The status of a whole render (its start, then its end) and the message that came with it.
  BounceStatus render_status(std::string& message) {
    BounceStatus status = bounce_render_start(engine_, &settings_, &camera_);
    if (status == BOUNCE_OK) status = bounce_render_wait(engine_, -1);
    message = status == BOUNCE_OK ? "" : bounce_last_error();
    return status;
  }
  // The same render from an engine that never failed.
  Image fresh_render() {
    std::swap(engine_, fresh_);
    EXPECT_EQ(bounce_engine_create(nullptr, &engine_), BOUNCE_OK) << bounce_last_error();
    build_scene();
    const Image image = render();
    bounce_engine_destroy(engine_);
    std::swap(engine_, fresh_);
    return image;
  }
  static bool lit(const Image& image) { return mean_red(image) > 0.01; }

  BounceEngine* fresh_ = nullptr;
};

TEST_F(FailureInjection, NoEglDisplayFailsEngineCreationAndTheNextEngineWorks) {
  inject("egl");
  BounceEngine* engine = nullptr;
  EXPECT_EQ(bounce_engine_create(nullptr, &engine), BOUNCE_ERROR_CONTEXT);
  EXPECT_EQ(engine, nullptr);
  EXPECT_NE(std::string(bounce_last_error()).find("no EGL display"), std::string::npos) << bounce_last_error();
  heal();
  ASSERT_BOUNCE_OK(bounce_engine_create(nullptr, &engine));
  std::swap(engine, engine_);
  build_scene();
  const Image image = render();
  std::swap(engine, engine_);
  bounce_engine_destroy(engine);
  EXPECT_TRUE(all_finite(image));
  EXPECT_TRUE(lit(image));
}

// A frame of a new size, then a shadow map of a new size, cannot be allocated: the render fails with GL's
// message, and the same engine's next render equals a render by an engine that never failed.
TEST_F(FailureInjection, GpuOutOfMemoryFailsTheRenderAndTheEngineRecovers) {
  build_scene();
  settings_.shadow_method = BOUNCE_SHADOWS_MAPS;
  render();
  struct Case {
    const char* what;
    int width, shadow_map_size;
  };
  for (const Case& c : {Case{"frame", 64, 1024}, Case{"shadow map", 64, 2048}}) {
    SCOPED_TRACE(c.what);
    camera_.width = c.width;
    settings_.shadow_map_size = c.shadow_map_size;
    inject("gl-oom");
    std::string message;
    EXPECT_EQ(render_status(message), BOUNCE_ERROR_GL);
    EXPECT_NE(message.find("out of GPU memory"), std::string::npos) << message;
    heal();
    const Image recovered = render();
    EXPECT_TRUE(lit(recovered));
    EXPECT_EQ(recovered.values, fresh_render().values);
  }
}

// Without Embree the engine still starts; what needs rays fails with a message that names the way out (shadow
// maps), that way out renders, and the same engine traces rays once Embree starts.
TEST_F(FailureInjection, EmbreeThatCannotStartFailsOnlyWhatNeedsRays) {
  inject("embree");
  BounceEngine* engine = nullptr;
  ASSERT_BOUNCE_OK(bounce_engine_create(nullptr, &engine));
  std::swap(engine, engine_);
  bounce_engine_destroy(engine);
  build_scene();
  for (int32_t method : {BOUNCE_METHOD_DIRECT, BOUNCE_METHOD_TOPOLOGY, BOUNCE_METHOD_AUTO}) {
    SCOPED_TRACE(method);
    settings_.method = method;
    settings_.shadow_method = BOUNCE_SHADOWS_RAY_TRACED;
    std::string message;
    EXPECT_EQ(render_status(message), BOUNCE_ERROR_RAY_TRACING);
    EXPECT_NE(message.find("Embree could not start"), std::string::npos) << message;
    EXPECT_NE(message.find("Shadow Maps"), std::string::npos) << message;
  }
  settings_.method = BOUNCE_METHOD_DIRECT;
  settings_.shadow_method = BOUNCE_SHADOWS_MAPS;
  EXPECT_TRUE(lit(render()));
  heal();
  settings_.shadow_method = BOUNCE_SHADOWS_RAY_TRACED;
  const Image traced = render();
  EXPECT_TRUE(lit(traced));
  EXPECT_EQ(traced.values, fresh_render().values);
}

}  // namespace
}  // namespace bounce::test
