// Settings.time_limit: a render adds samples while the next one, at the mean time of those done, still ends
// within the limit. The first sample always renders, so a limit shorter than one sample gives one sample.
#pragma once

#include <chrono>

namespace bounce {

class TimeLimit {
 public:
  explicit TimeLimit(float seconds) : seconds_(seconds), started_(std::chrono::steady_clock::now()) {}
  bool another_fits(int samples_done) const {
    if (!(seconds_ > 0.0f) || samples_done <= 0) return true;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    return elapsed * (samples_done + 1) / samples_done <= seconds_;
  }

 private:
  float seconds_;
  std::chrono::steady_clock::time_point started_;
};

}  // namespace bounce
