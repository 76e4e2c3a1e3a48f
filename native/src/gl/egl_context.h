// A headless OpenGL 4.5 core context through EGL, made current on the calling thread (the render thread).
#pragma once

#include <epoxy/egl.h>

#include <string>

namespace bounce::gl {

class EglContext {
 public:
  // platform: "surfaceless" (Mesa), "device" (EGL_EXT_platform_device, headless NVIDIA) or "" for the
  // BOUNCE_EGL_PLATFORM environment variable, else surfaceless with device as the fallback.
  EglContext(const std::string& platform, bool debug);
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  const std::string& description() const { return description_; }

 private:
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  std::string description_;
};

}  // namespace bounce::gl
