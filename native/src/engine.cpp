#include "engine.h"

#include <chrono>
#include <cmath>
#include <cstring>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "error.h"
#include "renderer.h"
#include "scene_data.h"
#include "settings.h"

namespace bounce {

namespace {

void validate_camera(const BounceCamera& camera) {
  require(camera.width >= 1 && camera.height >= 1 && camera.width <= 65536 && camera.height <= 65536,
          "camera: image size " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
              " is outside 1..65536");
  for (float v : camera.world_to_view) require(std::isfinite(v), "camera: view matrix is not finite");
  for (float v : camera.projection) require(std::isfinite(v), "camera: projection matrix is not finite");
  // Blender gives an all-zero matrix for an orthographic scale of 0: every point would land on w = 0, unseen.
  const double determinant = glm::determinant(glm::dmat4(glm::make_mat4(camera.projection)));
  require(determinant != 0.0 && std::isfinite(determinant),
          "camera: the projection matrix is singular (an orthographic scale or focal length of zero?)");
  const int32_t* c = camera.crop;
  const bool whole = c[0] == 0 && c[1] == 0 && c[2] == 0 && c[3] == 0;
  require(
      whole || (c[0] >= 0 && c[1] >= 0 && c[2] <= camera.width && c[3] <= camera.height && c[0] < c[2] && c[1] < c[3]),
      "camera: crop (" + std::to_string(c[0]) + ", " + std::to_string(c[1]) + ", " + std::to_string(c[2]) + ", " +
          std::to_string(c[3]) + ") is empty or outside the image");
}

}  // namespace

Engine::Engine(const BounceEngineDesc& desc) : thread_(desc.egl_platform ? desc.egl_platform : "", desc.debug_gl != 0) {
  thread_.run([this] { renderer_ = std::make_unique<Renderer>(); });
  thread_.set_exit_task([this] { renderer_.reset(); });
}

Engine::~Engine() { generation_.fetch_add(1); }

void Engine::post_scene_edit(std::function<void()> edit) {
  thread_.post([this, edit = std::move(edit)] {
    try {
      edit();
    } catch (const std::exception& e) {
      std::lock_guard lock(mutex_);
      scene_error_ = e.what();
    }
  });
}

void Engine::set_mesh(uint64_t key, const BounceMeshDesc& mesh) {
  auto data = prepare_mesh(key, mesh);
  post_scene_edit([this, key, data] { renderer_->scene().set_mesh(key, data); });
}

void Engine::remove_mesh(uint64_t key) {
  post_scene_edit([this, key] { renderer_->scene().remove_mesh(key); });
}

void Engine::set_texture(uint64_t key, int32_t width, int32_t height, int32_t format, const void* pixels) {
  auto data = prepare_texture(key, width, height, format, pixels);
  post_scene_edit([this, key, data] { renderer_->scene().set_texture(key, data); });
}

void Engine::remove_texture(uint64_t key) {
  post_scene_edit([this, key] { renderer_->scene().remove_texture(key); });
}

void Engine::set_materials(uint32_t count, const BounceMaterial* materials) {
  auto data = prepare_materials(count, materials);
  post_scene_edit([this, data = std::move(data)]() mutable { renderer_->scene().set_materials(std::move(data)); });
}

void Engine::set_instances(const BounceInstancesDesc& instances) {
  auto data = prepare_instances(instances);
  post_scene_edit([this, data] { renderer_->scene().set_instances(data); });
}

void Engine::set_lights(uint32_t count, const BounceLight* lights) {
  auto data = prepare_lights(count, lights);
  post_scene_edit([this, data = std::move(data)]() mutable { renderer_->scene().set_lights(std::move(data)); });
}

void Engine::set_world(const BounceWorld& world) {
  BounceWorld w = world;
  for (float& c : w.background) c = std::isfinite(c) ? std::clamp(c, 0.0f, kMaxIntensity) : 0.0f;
  // Only the direction the mapping gives is looked up: it is scaled to a largest entry of 1, so that a huge
  // entry cannot overflow a direction (1e30 x 1e30 is no float). A non-finite or singular mapping (a Mapping node
  // scaled to 0, or one axis 1e12 times another) maps nothing: the identity instead.
  glm::mat3 mapping = glm::make_mat3(w.world_to_environment);
  float largest = 0.0f;
  for (int column = 0; column < 3; ++column)
    for (int row = 0; row < 3; ++row) largest = std::max(largest, std::abs(mapping[column][row]));
  if (std::isfinite(largest) && largest > 0.0f) {
    mapping /= largest;
    std::memcpy(w.world_to_environment, &mapping[0][0], sizeof w.world_to_environment);
  }
  const float det = glm::determinant(mapping);
  if (!std::isfinite(det) || std::abs(det) < 1e-12f) {
    const glm::mat3 identity(1.0f);
    std::memcpy(w.world_to_environment, &identity[0][0], sizeof w.world_to_environment);
  }
  post_scene_edit([this, w] { renderer_->scene().set_world(w); });
}

BounceSceneStats Engine::scene_stats() {
  BounceSceneStats stats{};
  thread_.run([&] {
    renderer_->scene().prepare();
    stats = renderer_->scene().stats();
  });
  return stats;
}

void Engine::render_start(const BounceSettings& settings, const BounceCamera& camera) {
  validate_settings(settings);
  validate_camera(camera);
  uint64_t generation;
  {
    std::lock_guard lock(mutex_);
    generation = generation_.fetch_add(1) + 1;
    progress_.state = BOUNCE_RENDER_RUNNING;
    progress_.samples_done = 0;
    progress_.samples_total = settings.samples;
    progress_.progress = 0.0f;
    progress_.stage[0] = '\0';
    render_status_ = BOUNCE_OK;
    render_error_.clear();
  }
  state_changed_.notify_all();
  thread_.post([this, settings, camera, generation] { run_render(settings, camera, generation); });
}

void Engine::render_cancel() {
  std::lock_guard lock(mutex_);
  generation_.fetch_add(1);
  if (progress_.state == BOUNCE_RENDER_RUNNING) progress_.state = BOUNCE_RENDER_CANCELLED;
  state_changed_.notify_all();
}

void Engine::finish(uint64_t generation, BounceRenderState state, BounceStatus status, const std::string& message) {
  std::lock_guard lock(mutex_);
  if (generation != generation_.load()) return;
  progress_.state = state;
  render_status_ = status;
  render_error_ = message;
  state_changed_.notify_all();
}

void Engine::run_render(const BounceSettings& settings, const BounceCamera& camera, uint64_t generation) {
  if (generation != generation_.load()) return;  // superseded while queued
  try {
    {
      std::lock_guard lock(mutex_);
      if (!scene_error_.empty()) {
        const std::string message = "the scene could not be uploaded: " + scene_error_;
        scene_error_.clear();
        fail(BOUNCE_ERROR_GL, message);
      }
    }
    RenderCallbacks callbacks;
    callbacks.cancelled = [this, generation] { return generation != generation_.load(); };
    callbacks.progress = [this, generation](int samples_done, float fraction) {
      std::lock_guard lock(mutex_);
      if (generation != generation_.load()) return;
      progress_.samples_done = samples_done;
      progress_.progress = fraction;
      progress_.stage[0] = '\0';
    };
    callbacks.status = [this, generation](const char* stage, float fraction) {
      std::lock_guard lock(mutex_);
      if (generation != generation_.load()) return;
      std::strncpy(progress_.stage, stage, sizeof progress_.stage - 1);
      progress_.stage[sizeof progress_.stage - 1] = '\0';
      progress_.progress = fraction;
    };
    callbacks.publish = [this, generation](std::shared_ptr<Frame> frame) {
      std::lock_guard lock(mutex_);
      if (generation != generation_.load()) return;
      frame->info.serial = ++frame_serial_;
      progress_.frame_serial = frame_serial_;
      frame_ = std::move(frame);
      state_changed_.notify_all();
    };
    const bool completed = renderer_->render(settings, camera, callbacks);
    if (auto topology = renderer_->topology()) {
      std::lock_guard lock(mutex_);
      topology_ = std::move(topology);
    }
    finish(generation, completed ? BOUNCE_RENDER_DONE : BOUNCE_RENDER_CANCELLED,
           completed ? BOUNCE_OK : BOUNCE_ERROR_CANCELLED, completed ? "" : "the render was cancelled");
  } catch (const Error& e) {
    finish(generation, BOUNCE_RENDER_FAILED, e.status(), e.what());
  } catch (const std::bad_alloc&) {
    finish(generation, BOUNCE_RENDER_FAILED, BOUNCE_ERROR_OUT_OF_MEMORY, "out of memory while rendering");
  } catch (const std::exception& e) {
    finish(generation, BOUNCE_RENDER_FAILED, BOUNCE_ERROR_INTERNAL, e.what());
  }
}

BounceRenderProgress Engine::progress() {
  std::lock_guard lock(mutex_);
  return progress_;
}

void Engine::wait(int32_t timeout_ms) {
  std::unique_lock lock(mutex_);
  auto done = [this] { return progress_.state != BOUNCE_RENDER_RUNNING; };
  if (timeout_ms < 0)
    state_changed_.wait(lock, done);
  else if (!state_changed_.wait_for(lock, std::chrono::milliseconds(timeout_ms), done))
    fail(BOUNCE_ERROR_NOT_READY, "the render is still running");
  if (progress_.state == BOUNCE_RENDER_CANCELLED) fail(BOUNCE_ERROR_CANCELLED, "the render was cancelled");
  if (progress_.state == BOUNCE_RENDER_FAILED) fail(render_status_, render_error_);
}

BounceFrameInfo Engine::frame_info() {
  std::lock_guard lock(mutex_);
  if (!frame_) fail(BOUNCE_ERROR_NOT_READY, "no frame has been rendered yet");
  described_ = frame_;
  return frame_->info;
}

void Engine::frame_read(int32_t aov, float* dst, std::size_t float_count) {
  require(aov >= 0 && aov < BOUNCE_AOV_COUNT, "unknown AOV " + std::to_string(aov));
  require(dst != nullptr, "frame_read: dst is NULL");
  std::shared_ptr<const Frame> frame;
  {
    std::lock_guard lock(mutex_);
    frame = described_;
  }
  if (!frame) fail(BOUNCE_ERROR_NOT_READY, "call bounce_frame_info first: no frame has been described yet");
  const std::size_t expected = std::size_t(frame->width) * frame->height * bounce_aov_channels(aov);
  require(float_count == expected, "frame_read: dst holds " + std::to_string(float_count) + " floats, the " +
                                       bounce_aov_name(aov) + " AOV has " + std::to_string(expected));
  if (frame->holds(aov))
    std::memcpy(dst, frame->aovs[aov].data(), expected * sizeof(float));
  else
    std::fill(dst, dst + expected, 0.0f);  // not written by the frame's method
}

std::shared_ptr<const topology::Topology> Engine::topology() {
  std::lock_guard lock(mutex_);
  return topology_;
}

}  // namespace bounce
