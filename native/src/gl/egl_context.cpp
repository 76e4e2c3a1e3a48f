#include "gl/egl_context.h"

#include <epoxy/gl.h>

#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <vector>

#include "common/fault_injection.h"
#include "error.h"

namespace bounce::gl {

namespace {

std::string egl_error_text(const char* what) {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, "%s failed (EGL error 0x%04x)", what, eglGetError());
  return buffer;
}

EGLDisplay surfaceless_display() {
  return eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
}

EGLDisplay device_display() {
  // NVIDIA's EGL (through libglvnd) lists EGL_EXT_device_base, which includes device enumeration, and not
  // EGL_EXT_device_enumeration itself.
  if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration") &&
      !epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_base"))
    return EGL_NO_DISPLAY;
  EGLint count = 0;
  eglQueryDevicesEXT(0, nullptr, &count);
  std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
  if (count == 0 || !eglQueryDevicesEXT(count, devices.data(), &count)) return EGL_NO_DISPLAY;
  for (EGLDeviceEXT device : devices) {
    EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
    if (display != EGL_NO_DISPLAY && eglInitialize(display, nullptr, nullptr)) return display;
  }
  return EGL_NO_DISPLAY;
}

// Displays are shared by every engine of the process and never terminated: eglTerminate would pull the
// display from under another engine's live context (the viewport and F12 engines coexist).
EGLDisplay shared_display(const std::string& platform, std::string& chosen) {
  static std::mutex mutex;
  std::lock_guard lock(mutex);
  static EGLDisplay surfaceless = EGL_NO_DISPLAY, device = EGL_NO_DISPLAY;
  const bool want_device = platform == "device";
  if (!want_device) {
    if (surfaceless == EGL_NO_DISPLAY) {
      EGLDisplay display = surfaceless_display();
      if (display != EGL_NO_DISPLAY && eglInitialize(display, nullptr, nullptr)) surfaceless = display;
    }
    chosen = "surfaceless";
    if (surfaceless != EGL_NO_DISPLAY || platform == "surfaceless") return surfaceless;
  }
  if (device == EGL_NO_DISPLAY) device = device_display();
  chosen = "device";
  return device;
}

void debug_callback(GLenum, GLenum type, GLuint, GLenum severity, GLsizei, const GLchar* message, const void*) {
  if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
  std::fprintf(stderr, "bounce: GL %s: %s\n", type == GL_DEBUG_TYPE_ERROR ? "error" : "debug", message);
}

}  // namespace

EglContext::EglContext(const std::string& requested_platform, bool debug) {
  std::string platform = requested_platform;
  if (platform.empty()) {
    const char* env = std::getenv("BOUNCE_EGL_PLATFORM");
    platform = env ? env : "";
  }
  if (!platform.empty() && platform != "surfaceless" && platform != "device")
    fail(BOUNCE_ERROR_INVALID_ARGUMENT,
         "EGL platform '" + platform + "' is not one of 'surfaceless', 'device' (BOUNCE_EGL_PLATFORM)");

  std::string chosen = platform.empty() ? "surfaceless" : platform;
  display_ = fault_injected("egl") ? EGL_NO_DISPLAY : shared_display(platform, chosen);
  if (display_ == EGL_NO_DISPLAY)
    fail(BOUNCE_ERROR_CONTEXT,
         "no EGL display for platform '" + chosen + "': install Mesa's EGL (libegl-mesa0) or a GPU driver with EGL");
  if (!eglBindAPI(EGL_OPENGL_API)) fail(BOUNCE_ERROR_CONTEXT, egl_error_text("eglBindAPI(EGL_OPENGL_API)"));
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                               4,
                               EGL_CONTEXT_MINOR_VERSION,
                               5,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                               EGL_CONTEXT_OPENGL_DEBUG,
                               debug ? EGL_TRUE : EGL_FALSE,
                               EGL_NONE};
  context_ = eglCreateContext(display_, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
  if (context_ == EGL_NO_CONTEXT)
    fail(BOUNCE_ERROR_CONTEXT, egl_error_text("eglCreateContext(OpenGL 4.5 core)") +
                                   ": the driver needs OpenGL 4.5 core and EGL_KHR_no_config_context");
  if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
    const std::string message = egl_error_text("eglMakeCurrent(surfaceless)");
    eglDestroyContext(display_, context_);
    fail(BOUNCE_ERROR_CONTEXT, message);
  }
  // BOUNCE_DEBUG_GL=1 turns the driver's messages on for every caller (the add-on, the tests), to diagnose a driver.
  const char* debug_env = std::getenv("BOUNCE_DEBUG_GL");
  if (debug || (debug_env && *debug_env && std::string(debug_env) != "0")) {
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(debug_callback, nullptr);
  }
  description_ = std::string(reinterpret_cast<const char*>(glGetString(GL_RENDERER))) + " | " +
                 reinterpret_cast<const char*>(glGetString(GL_VERSION)) + " | EGL " + chosen;
}

EglContext::~EglContext() {
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  eglReleaseThread();
}

}  // namespace bounce::gl
