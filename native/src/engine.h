// The object behind a BounceEngine handle: scene edits and renders go to its render thread; progress and the
// latest frame come back under a lock.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>

#include "bounce/bounce.h"
#include "frame.h"
#include "render_thread.h"

namespace bounce {

class Renderer;
namespace topology {
struct Topology;
}

class Engine {
 public:
  explicit Engine(const BounceEngineDesc& desc);
  ~Engine();

  void set_mesh(uint64_t key, const BounceMeshDesc& mesh);
  void remove_mesh(uint64_t key);
  void set_texture(uint64_t key, int32_t width, int32_t height, int32_t format, const void* pixels);
  void remove_texture(uint64_t key);
  void set_materials(uint32_t count, const BounceMaterial* materials);
  void set_instances(const BounceInstancesDesc& instances);
  void set_lights(uint32_t count, const BounceLight* lights);
  void set_world(const BounceWorld& world);
  BounceSceneStats scene_stats();

  void render_start(const BounceSettings& settings, const BounceCamera& camera);
  void render_cancel();
  BounceRenderProgress progress();
  void wait(int32_t timeout_ms);  // throws Error for a failed, cancelled or unfinished render
  BounceFrameInfo frame_info();
  void frame_read(int32_t aov, float* dst, std::size_t float_count);
  const std::string& gl_description() const { return thread_.gl_description(); }
  // The topology the last TOPOLOGY render used; nullptr before one.
  std::shared_ptr<const topology::Topology> topology();

 private:
  // Runs a scene edit on the render thread; a failure there (e.g. out of GPU memory) fails the next render.
  void post_scene_edit(std::function<void()> edit);
  void run_render(const BounceSettings& settings, const BounceCamera& camera, uint64_t generation);
  void finish(uint64_t generation, BounceRenderState state, BounceStatus status, const std::string& message);

  std::unique_ptr<Renderer> renderer_;  // made and destroyed on the render thread

  std::mutex mutex_;
  std::condition_variable state_changed_;
  std::atomic<uint64_t> generation_{0};
  BounceRenderProgress progress_{};
  BounceStatus render_status_ = BOUNCE_OK;
  std::string render_error_;
  std::string scene_error_;
  std::shared_ptr<const Frame> frame_;  // the latest published frame
  std::shared_ptr<const topology::Topology> topology_;
  std::shared_ptr<const Frame> described_;  // the frame the last frame_info() described, for frame_read()
  uint64_t frame_serial_ = 0;

  RenderThread thread_;  // last: joined first on destruction, while the state above still exists
};

}  // namespace bounce
