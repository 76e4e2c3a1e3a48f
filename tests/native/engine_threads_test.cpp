// The engine handle from several threads, as Blender uses it: the viewport polls frames while the render thread
// renders, F12 starts a second engine, a user edits the scene or closes the viewport mid-render. These pass in the
// plain build; the ThreadSanitizer build (README, "Testing": scripts/tsan) runs them to find data races.
#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <thread>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include "common/parallel.h"
#include "render_fixture.h"
#include "render_thread.h"

namespace bounce::test {
namespace {

constexpr int32_t kMethods[] = {BOUNCE_METHOD_DIRECT, BOUNCE_METHOD_FLC, BOUNCE_METHOD_SSVP, BOUNCE_METHOD_TOPOLOGY,
                                BOUNCE_METHOD_AUTO};

class EngineThreads : public RenderFixture {
 protected:
  void SetUp() override {
    RenderFixture::SetUp();
    const glm::mat4 view = glm::lookAt(glm::vec3(0, -6, 4), glm::vec3(0), glm::vec3(0, 0, 1));
    set_camera(view, glm::perspective(0.8f, 1.5f, 0.1f, 100.0f), 24, 16);
  }
  // A floor and a floating block under a sun, into `engine`.
  void build_scene(BounceEngine* engine, float albedo = 0.5f, float sun = 3.0f) {
    std::swap(engine, engine_);
    add_plane(1, 20.0f);
    add_plane(2, 2.0f);
    set_instances({1, 2}, {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, 0, 1))});
    set_albedo(albedo);
    set_lights({make_light(BOUNCE_LIGHT_SUN, {0, 0, 10}, glm::vec3(sun))});
    std::swap(engine, engine_);
  }
  BounceEngine* new_engine() {
    BounceEngine* engine = nullptr;
    EXPECT_EQ(bounce_engine_create(nullptr, &engine), BOUNCE_OK) << bounce_last_error();
    return engine;
  }
  Image render_with(BounceEngine* engine) {
    std::swap(engine, engine_);
    Image image = render();
    std::swap(engine, engine_);
    return image;
  }
  void start_long_render(int32_t method) {
    settings_.method = method;
    settings_.samples = 5000;
    ASSERT_BOUNCE_OK(bounce_render_start(engine_, &settings_, &camera_));
  }
  // Waits until the running render has published a frame (or ended).
  void wait_for_a_frame() {
    for (int i = 0; i < 2000; ++i) {
      BounceRenderProgress progress{};
      ASSERT_BOUNCE_OK(bounce_render_progress(engine_, &progress));
      if (progress.frame_serial > 0 || progress.state != BOUNCE_RENDER_RUNNING) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    FAIL() << "no frame within 10 s";
  }
};

// Closing the viewport or Blender mid-render: the render stops and the engine goes, with no wait for 5,000
// samples and no crash.
TEST_F(EngineThreads, DestroyDuringRender) {
  for (int32_t method : kMethods) {
    SCOPED_TRACE(method);
    BounceEngine* engine = new_engine();
    build_scene(engine);
    std::swap(engine, engine_);
    start_long_render(method);
    wait_for_a_frame();
    std::swap(engine, engine_);
    const auto start = std::chrono::steady_clock::now();
    bounce_engine_destroy(engine);
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(60));
  }
}

// Edits made while a render runs are queued behind it; the next render sees all of them, exactly as an engine
// given the edited scene from the start.
TEST_F(EngineThreads, SceneEditsDuringRenderReachTheNextRender) {
  build_scene(engine_);
  start_long_render(BOUNCE_METHOD_DIRECT);
  wait_for_a_frame();
  for (int i = 0; i < 5; ++i) build_scene(engine_, 0.3f + 0.05f * i, 1.0f + i);
  ASSERT_BOUNCE_OK(bounce_render_cancel(engine_));
  EXPECT_EQ(bounce_render_wait(engine_, -1), BOUNCE_ERROR_CANCELLED);
  settings_.samples = 2;
  const Image edited = render();
  BounceEngine* fresh = new_engine();
  build_scene(fresh, 0.5f, 5.0f);
  const Image expected = render_with(fresh);
  bounce_engine_destroy(fresh);
  EXPECT_EQ(edited.values, expected.values);
}

// The viewport's pattern, from two threads at once: progress, frame info and frame reads while the render
// thread publishes progressive frames.
TEST_F(EngineThreads, FramesReadWhileRendering) {
  build_scene(engine_);
  for (int32_t method : kMethods) {
    SCOPED_TRACE(method);
    settings_.method = method;
    settings_.samples = 6;
    ASSERT_BOUNCE_OK(bounce_render_start(engine_, &settings_, &camera_));
    std::atomic<bool> done{false};
    std::atomic<int> bad_frames{0};
    auto poll = [&] {
      std::vector<float> pixels;
      while (!done) {
        BounceRenderProgress progress{};
        bounce_render_progress(engine_, &progress);
        BounceFrameInfo info{};
        if (bounce_frame_info(engine_, &info) != BOUNCE_OK) continue;
        pixels.resize(std::size_t(info.width) * info.height * 4);
        if (bounce_frame_read(engine_, BOUNCE_AOV_COMBINED, pixels.data(), pixels.size()) != BOUNCE_OK) continue;
        for (float v : pixels)
          if (!std::isfinite(v)) ++bad_frames;
      }
    };
    std::thread viewport(poll), ui(poll);
    EXPECT_EQ(bounce_render_wait(engine_, -1), BOUNCE_OK) << bounce_last_error();
    done = true;
    viewport.join();
    ui.join();
    EXPECT_EQ(bad_frames, 0);
  }
}

// F12 while the viewport renders: two engines on two threads, each image the same as when rendered alone.
TEST_F(EngineThreads, TwoEnginesOnTwoThreads) {
  const int32_t pair[2] = {BOUNCE_METHOD_TOPOLOGY, BOUNCE_METHOD_FLC};
  BounceEngine* engines[2] = {new_engine(), new_engine()};
  Image alone[2], together[2];
  for (int i = 0; i < 2; ++i) {
    build_scene(engines[i]);
    settings_.method = pair[i];
    alone[i] = render_with(engines[i]);
  }
  auto render_on = [&](int i) {
    BounceSettings settings = settings_;
    settings.method = pair[i];
    EXPECT_EQ(bounce_render_start(engines[i], &settings, &camera_), BOUNCE_OK);
    EXPECT_EQ(bounce_render_wait(engines[i], -1), BOUNCE_OK);
    BounceFrameInfo info{};
    EXPECT_EQ(bounce_frame_info(engines[i], &info), BOUNCE_OK);
    together[i].values.resize(std::size_t(info.width) * info.height * 4);
    EXPECT_EQ(bounce_frame_read(engines[i], BOUNCE_AOV_COMBINED, together[i].values.data(), together[i].values.size()),
              BOUNCE_OK);
  };
  std::thread first(render_on, 0), second(render_on, 1);
  first.join();
  second.join();
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(together[i].values, alone[i].values) << "method " << pair[i];
    bounce_engine_destroy(engines[i]);
  }
}

// A user dragging a slider: renders started and superseded in quick succession; the last one finishes.
TEST_F(EngineThreads, RendersSupersededInQuickSuccession) {
  build_scene(engine_);
  settings_.samples = 200;
  for (int i = 0; i < 20; ++i) {
    settings_.method = kMethods[i % 5];
    ASSERT_BOUNCE_OK(bounce_render_start(engine_, &settings_, &camera_));
    if (i % 3 == 0) {
      ASSERT_BOUNCE_OK(bounce_render_cancel(engine_));
    }
  }
  settings_.samples = 1;
  EXPECT_TRUE(all_finite(render()));
}

#if defined(__SSE__)
// The render thread starts in the floating-point mode of the thread that creates the engine, which in Blender
// differs from one process to another; SSVP's clusters came out differently where tiny sums were denormal on one
// thread and flushed on another (the budget's two rooms, left third: 1.08 in one Blender process, 1.16 in the
// next). The render thread fixes its mode (denormals flushed, round to nearest) whatever its creator's, and the
// workers of its parallel loops take it over.
TEST(RenderThreadFloatMode, IsFixedWhateverTheCreatorsAndWorkersShareIt) {
  constexpr unsigned int kFixed = 0x9FC0;
  const unsigned int creator_mode = _mm_getcsr();
  for (const unsigned int creator : {0x1F80u, 0x9FC0u, 0x7F80u}) {  // default; FTZ and DAZ; round towards zero
    _mm_setcsr(creator);
    std::unique_ptr<RenderThread> thread;
    try {
      thread = std::make_unique<RenderThread>("", false);
    } catch (...) {
      _mm_setcsr(creator_mode);
      throw;
    }
    _mm_setcsr(creator_mode);
    unsigned int render_thread_mode = 0;
    std::set<unsigned int> worker_modes;
    std::mutex worker_modes_mutex;
    thread->run([&] {
      render_thread_mode = _mm_getcsr();
      parallel_for(64, 4, 1, [&](std::size_t) {
        const unsigned int mode = _mm_getcsr();
        std::lock_guard lock(worker_modes_mutex);
        worker_modes.insert(mode);
      });
    });
    EXPECT_EQ(render_thread_mode & ~0x3Fu, kFixed) << "creator's mode " << std::hex << creator;  // flags aside
    ASSERT_EQ(worker_modes.size(), 1u);
    EXPECT_EQ(*worker_modes.begin() & ~0x3Fu, kFixed);
  }
}
#endif

}  // namespace
}  // namespace bounce::test
