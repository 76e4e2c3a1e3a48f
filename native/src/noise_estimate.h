// The noise a progressive render's samples leave, estimated from the frames it publishes. For independent samples
// of variance v, the image after a samples differs from the one after N by v (1/a - 1/N) per value, so the final
// image's noise variance v / N is that squared difference times a / (N - a). The estimate is the benchmarks'
// relMSE (mean of (x - r)^2 / (r^2 + 0.01) over the RGB values of Combined) of the noise alone, the converged image
// standing for r. Samples are stratified against each other (jitter, world directions, and each pixel's shadow
// and near-field rays spread over the samples: cpu::Progression), so the two halves of a render are not
// independent: where one half fills the gaps of the other, their difference overstates the noise of the whole.
// On the sky-occlusion test (tests/native/noise_estimate_test.cpp) the estimate is 2.7 times the noise measured
// against a converged render at 8 samples and 2.0 times at 32; with independent rays per pixel and the sky's
// directions shared by all pixels it was 2 to 4 times below.
#pragma once

#include <vector>

#include "frame.h"

namespace bounce {

class NoiseEstimate {
 public:
  // The frames a render publishes whatever its publishing interval, and the only ones the estimate keeps: after
  // 1, 2, 4, 8, ... samples (where Noise Target is checked, each against the one before, and which a render that
  // Time Limit stops early is estimated against) and half-way through (against which a render of all its samples
  // is estimated: half the samples against the other half).
  static bool checkpoint(int samples_done, int samples) {
    return samples_done == samples / 2 || (samples_done > 0 && (samples_done & (samples_done - 1)) == 0);
  }

  // A partial frame of `samples_done` of `samples` published: kept if a checkpoint up to half-way. Returns whether,
  // at a checkpoint, its estimated noise is at most `target` (Noise Target; never for 0).
  bool add_partial(const Frame& partial, int samples_done, int samples, float target) {
    if (!checkpoint(samples_done, samples)) return false;
    checkpoint_noise_ = relmse(partial, samples_done);
    checkpoint_samples_ = samples_done;
    if (samples_done <= samples / 2) {
      combined_ = partial.aovs[BOUNCE_AOV_COMBINED];
      samples_ = samples_done;
    }
    return target > 0.0f && checkpoint_noise_ >= 0.0f && checkpoint_noise_ <= target;
  }
  // The noise of a render's last frame: against the frame kept last, or where the render stopped at a checkpoint
  // (Noise Target), that checkpoint's estimate.
  float final_relmse(const Frame& frame, int samples_done) const {
    return samples_done == checkpoint_samples_ ? checkpoint_noise_ : relmse(frame, samples_done);
  }
  // The noise of `frame` (of `samples_done`) as relMSE, against the frame kept last; -1 without one of fewer
  // samples and the same size.
  float relmse(const Frame& frame, int samples_done) const {
    const std::vector<float>& last = frame.aovs[BOUNCE_AOV_COMBINED];
    if (samples_ <= 0 || samples_ >= samples_done || combined_.size() != last.size() || last.empty()) return -1.0f;
    const double scale = double(samples_) / double(samples_done - samples_);
    double sum = 0.0;
    for (std::size_t i = 0; i < last.size(); i += 4)
      for (std::size_t c = 0; c < 3; ++c) {
        const double d = double(combined_[i + c]) - double(last[i + c]);
        sum += d * d * scale / (double(last[i + c]) * last[i + c] + 0.01);
      }
    return float(sum / double(3 * (last.size() / 4)));
  }

 private:
  std::vector<float> combined_;
  int samples_ = 0;
  float checkpoint_noise_ = -1.0f;
  int checkpoint_samples_ = 0;
};

}  // namespace bounce
