// Failure injection, for tests of what a user sees when a machine lacks what Bounce needs. BOUNCE_INJECT_FAULT
// names the failures to simulate, comma separated:
//   egl      no EGL display: creating an engine fails as on a machine without EGL
//   gl-oom   every texture allocation fails as a driver out of GPU memory does (frames, shadow maps, textures)
//   embree   Embree cannot create a device
//   low-gpu-memory  a frame's accumulation targets never fit in GPU memory at once: its tiles take turns
// Read at each point of failure, not once, so that a test turns a failure on and off between renders.
#pragma once

#include <cstdlib>
#include <string_view>

namespace bounce {

inline bool fault_injected(std::string_view fault) {
  const char* env = std::getenv("BOUNCE_INJECT_FAULT");
  std::string_view list = env ? env : "";
  while (!list.empty()) {
    const std::size_t comma = list.find(',');
    if (list.substr(0, comma) == fault) return true;
    if (comma == std::string_view::npos) break;
    list.remove_prefix(comma + 1);
  }
  return false;
}

}  // namespace bounce
