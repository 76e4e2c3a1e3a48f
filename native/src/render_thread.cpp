#include "render_thread.h"

#include <cstdio>

#include "common/parallel.h"
#include "gl/egl_context.h"

namespace bounce {

RenderThread::RenderThread(const std::string& egl_platform, bool debug_gl) {
  std::promise<void> started;
  std::future<void> ready = started.get_future();
  thread_ = std::thread([this, egl_platform, debug_gl, &started] { loop(egl_platform, debug_gl, started); });
  try {
    ready.get();
  } catch (...) {
    thread_.join();
    throw;
  }
}

RenderThread::~RenderThread() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void RenderThread::post(std::function<void()> task) {
  {
    std::lock_guard lock(mutex_);
    tasks_.push_back(std::move(task));
  }
  wake_.notify_all();
}

void RenderThread::run(const std::function<void()>& task) {
  std::promise<void> done;
  std::future<void> result = done.get_future();
  post([&] {
    try {
      task();
      done.set_value();
    } catch (...) {
      done.set_exception(std::current_exception());
    }
  });
  result.get();
}

void RenderThread::set_exit_task(std::function<void()> task) {
  std::lock_guard lock(mutex_);
  exit_task_ = std::move(task);
}

void RenderThread::loop(const std::string& egl_platform, bool debug_gl, std::promise<void>& started) {
  use_fixed_float_mode();
  std::unique_ptr<gl::EglContext> context;
  try {
    context = std::make_unique<gl::EglContext>(egl_platform, debug_gl);
    gl_description_ = context->description();
    started.set_value();
  } catch (...) {
    started.set_exception(std::current_exception());
    return;
  }
  for (;;) {
    std::function<void()> task;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || !tasks_.empty(); });
      if (tasks_.empty()) break;
      task = std::move(tasks_.front());
      tasks_.pop_front();
    }
    try {
      task();
    } catch (const std::exception& e) {
      // Posted tasks report their own failures; this only catches what escaped them.
      std::fprintf(stderr, "bounce: render thread task failed: %s\n", e.what());
    }
  }
  std::function<void()> exit_task;
  {
    std::lock_guard lock(mutex_);
    exit_task = std::move(exit_task_);
  }
  if (exit_task) exit_task();
}

}  // namespace bounce
