// The thread that owns an engine's GL context. Every GL call of the engine runs here, as a queued task.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace bounce {

namespace gl {
class EglContext;
}

class RenderThread {
 public:
  // Starts the thread and makes the context there; throws the context's Error if that fails.
  RenderThread(const std::string& egl_platform, bool debug_gl);
  ~RenderThread();  // runs the queued tasks, then `on_exit` (GL cleanup), then joins
  RenderThread(const RenderThread&) = delete;
  RenderThread& operator=(const RenderThread&) = delete;

  void post(std::function<void()> task);
  // Runs `task` on the render thread and waits; an exception it throws is rethrown here.
  void run(const std::function<void()>& task);
  void set_exit_task(std::function<void()> task);  // runs on the render thread before the context dies

  const std::string& gl_description() const { return gl_description_; }

 private:
  void loop(const std::string& egl_platform, bool debug_gl, std::promise<void>& started);

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> tasks_;
  std::function<void()> exit_task_;
  bool stopping_ = false;
  std::string gl_description_;
  std::thread thread_;
};

}  // namespace bounce
