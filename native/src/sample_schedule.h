// When a progressive render (any renderer) publishes a partial frame and when it stops adding samples: a partial
// frame after the first sample, at the noise estimate's checkpoints, and at least every 250 ms; no more samples
// once the next would overrun Time Limit (the first always renders) or a checkpoint meets Noise Target.
#pragma once

#include <chrono>

#include "bounce/bounce.h"
#include "noise_estimate.h"

namespace bounce {

class SampleSchedule {
 public:
  explicit SampleSchedule(const BounceSettings& settings)
      : time_limit_(settings.time_limit), noise_target_(settings.noise_target), samples_(settings.samples) {}

  // After `samples_done` samples: whether the next, at the mean time of those done, still ends within Time Limit.
  bool another_fits(int samples_done) const {
    if (!(time_limit_ > 0.0f) || samples_done <= 0) return true;
    const double elapsed = std::chrono::duration<double>(Clock::now() - started_).count();
    return elapsed * (samples_done + 1) / samples_done <= time_limit_;
  }
  // Whether a partial frame is due after `samples_done` samples (the last one's frame is the render's own).
  bool publish_due(int samples_done) const {
    return samples_done == 1 || NoiseEstimate::checkpoint(samples_done, samples_) ||
           Clock::now() - last_publish_ >= kPublishInterval;
  }
  // The AOVs a GPU render reads back into its partial frame of `samples_done` (those published before its last):
  // what a progressive display shows and the noise estimate reads. Reading every AOV back at each publish cost
  // 45-95 ms a sample at 1280x720 on an NVIDIA H100, a third of the frame.
  uint32_t partial_aovs(int samples_done) const { return NoiseEstimate::partial_aovs(samples_done, samples_); }
  // The partial frame of `samples_done` about to be published; true when it meets Noise Target, the last to render.
  bool published(const Frame& partial, int samples_done) {
    last_publish_ = Clock::now();
    return noise_.add_partial(partial, samples_done, samples_, noise_target_);
  }
  // Fills in the estimated noise of the render's last frame (NoiseEstimate::final_noise).
  void fill_noise(Frame& frame, int samples_done) const {
    const NoiseEstimate::Noise noise = noise_.final_noise(frame, samples_done);
    frame.info.noise_relmse = noise.relmse;
    frame.info.noise_direct_relmse = noise.direct_relmse;
    frame.info.noise_direct_rate = noise.direct_rate;
  }

 private:
  using Clock = std::chrono::steady_clock;
  static constexpr std::chrono::milliseconds kPublishInterval{250};
  float time_limit_, noise_target_;
  int samples_;
  Clock::time_point started_ = Clock::now(), last_publish_ = started_;
  NoiseEstimate noise_;
};

}  // namespace bounce
