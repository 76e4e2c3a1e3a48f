// The noise a progressive render's samples leave, estimated from the frames it publishes. For independent samples
// of variance v, the image after a samples differs from the one after N by v (1/a - 1/N) per value, so the final
// image's noise variance v / N is that squared difference times a / (N - a). The estimate is the benchmarks'
// relMSE (mean of (x - r)^2 / (r^2 + 0.01) over the RGB values of Combined) of the noise alone, the converged image
// standing for r. Samples are stratified against each other (jitter, world directions spread over the samples), so
// the two halves of a render are not independent: on the sky-occlusion test the estimate is 2 to 4 times below
// the noise measured against a converged render (tests/native/noise_estimate_test.cpp), and from the first sample
// instead of the half-way frame it would be 4 times above.
#pragma once

#include <vector>

#include "frame.h"

namespace bounce {

class NoiseEstimate {
 public:
  // A render publishes the frame half-way through its samples, whatever its publishing interval: the estimate
  // then compares half the samples with the other half.
  static bool half_way(int samples_done, int samples) { return samples_done == samples / 2; }

  // Keeps the Combined AOV of a partial frame of `samples_done` of `samples`, the latest up to half-way.
  void keep(const Frame& partial, int samples_done, int samples) {
    if (samples_done > samples / 2 && samples_ > 0) return;
    combined_ = partial.aovs[BOUNCE_AOV_COMBINED];
    samples_ = samples_done;
  }
  // The final frame's noise as relMSE; -1 without an earlier frame of fewer samples and the same size.
  float relmse(const Frame& final_frame, int samples_done) const {
    const std::vector<float>& last = final_frame.aovs[BOUNCE_AOV_COMBINED];
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
};

}  // namespace bounce
