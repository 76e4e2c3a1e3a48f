// The noise a progressive render's samples leave, estimated from the frames it publishes. The image after n samples
// of a sequence whose estimate has variance v n^-a differs from the image after N > n of the same sequence (nested)
// by v (n^-a - N^-a) per value, so the final image's noise variance v N^-a is that squared difference over
// (N / n)^a - 1. For independent samples a = 1. Each pixel's shadow, sky and near-field rays are stratified over
// its samples (cpu::Progression: Owen-scrambled Sobol points, whose variance falls as fast as N^-3 for smooth
// integrands, Owen 1997), so for the direct light a is above 1 and, taken as 1, the estimate was 2.7 times the
// measured noise at 8 samples and 2.0 times at 32 (the sky-occlusion test, tests/native/noise_estimate_test.cpp).
// The direct light's own a is measured from three nested frames, n_1 < n < N: the ratio of the squared differences
// (n_1^-a - n^-a) / (n^-a - N^-a), averaged with the a measured when the frame of n arrived: a 2D Sobol sequence
// refines one axis, then the other, so a alternates between octaves (the sky-occlusion test: 1.1 from 2 to 8
// samples, 2.0 from 4 to 16, 1.3 from 8 to 32). The rest of the image (the bounces, from VPLs drawn anew each sample: a
// heavy one in the first sample would pass for a fast rate) counts as independent. The estimate is the benchmarks'
// relMSE (mean of (x - r)^2 / (r^2 + 0.01) over the RGB values of Combined) of the noise alone, the last frame standing
// for r.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "frame.h"

namespace bounce {

class NoiseEstimate {
 public:
  // As relMSE (BounceFrameInfo's noise fields): the whole, and the Direct pass's part with its rate.
  struct Noise {
    float relmse = -1.0f;  // -1: unknown
    float direct_relmse = 0.0f;
    float direct_rate = 1.0f;
  };

  // The frames a render publishes whatever its publishing interval, and the only ones the estimate keeps: after
  // 1, 2, 4, 8, ... samples (where Noise Target is checked, each against the one before, and which a render that
  // Time Limit stops early is estimated against) and half-way through (against which a render of all its samples
  // is estimated: half the samples against the other half).
  static bool checkpoint(int samples_done, int samples) {
    return samples_done == samples / 2 || (samples_done > 0 && (samples_done & (samples_done - 1)) == 0);
  }
  // The AOVs the estimate reads from a partial frame of `samples_done`: Combined, and Direct at a checkpoint.
  static uint32_t partial_aovs(int samples_done, int samples) {
    return (1u << BOUNCE_AOV_COMBINED) | (checkpoint(samples_done, samples) ? 1u << BOUNCE_AOV_DIRECT : 0u);
  }

  // A partial frame of `samples_done` of `samples` published: kept if a checkpoint up to half-way. Returns whether,
  // at a checkpoint, its estimated noise is at most `target` (Noise Target; never for 0).
  bool add_partial(const Frame& partial, int samples_done, int samples, float target) {
    if (!checkpoint(samples_done, samples)) return false;
    const Estimate at_checkpoint = estimate(partial, samples_done);
    checkpoint_noise_ = at_checkpoint.noise;
    checkpoint_samples_ = samples_done;
    if (samples_done <= samples / 2) {
      earlier_ = std::move(kept_);
      std::vector<float>().swap(earlier_.combined);  // of the earlier frame, only the Direct pass is read
      kept_ = {partial.aovs[BOUNCE_AOV_COMBINED], partial.aovs[BOUNCE_AOV_DIRECT], samples_done,
               at_checkpoint.measured_rate};
    }
    return target > 0.0f && checkpoint_noise_.relmse >= 0.0f && checkpoint_noise_.relmse <= target;
  }
  // The noise of a render's last frame: against the frames kept last, or where the render stopped at a checkpoint
  // (Noise Target), that checkpoint's estimate.
  Noise final_noise(const Frame& frame, int samples_done) const {
    return samples_done == checkpoint_samples_ ? checkpoint_noise_ : estimate(frame, samples_done).noise;
  }

  // The a of variance v n^-a for which the squared difference between nested images of n_1 and n samples is `ratio`
  // times that between n and n_2 samples, within [1, 3] (independent samples, and Owen-scrambled nets on smooth
  // integrands); 1 where the ratio is not finite.
  static double convergence_rate(double ratio, int n_1, int n, int n_2) {
    const auto ratio_at = [&](double a) {
      return (std::pow(n_1, -a) - std::pow(n, -a)) / (std::pow(n, -a) - std::pow(n_2, -a));
    };
    double low = 1.0, high = 3.0;
    if (!std::isfinite(ratio) || ratio <= ratio_at(low)) return low;
    if (ratio >= ratio_at(high)) return high;
    for (int i = 0; i < 40; ++i) {
      const double mid = 0.5 * (low + high);
      (ratio_at(mid) < ratio ? low : high) = mid;
    }
    return 0.5 * (low + high);
  }

 private:
  struct Kept {
    std::vector<float> combined, direct;  // direct empty where the frame did not hold it, combined once earlier
    int samples = 0;
    double rate = 0.0;  // the direct light's a measured when the frame arrived; 0 where none was
  };
  struct Estimate {
    Noise noise;
    double measured_rate = 0.0;  // 0 where the frames gave none
  };

  // The noise of `frame` (of `samples_done`) as relMSE, against the frames kept last; -1 without one of fewer
  // samples and the same size.
  Estimate estimate(const Frame& frame, int samples_done) const {
    const std::vector<float>& last = frame.aovs[BOUNCE_AOV_COMBINED];
    const std::size_t pixels = last.size() / 4;
    if (kept_.samples <= 0 || kept_.samples >= samples_done || kept_.combined.size() != last.size() || last.empty())
      return {};
    const std::vector<float>& last_direct = frame.aovs[BOUNCE_AOV_DIRECT];
    const bool direct_apart = kept_.direct.size() == 3 * pixels && last_direct.size() == 3 * pixels;
    const bool rate_known = direct_apart && earlier_.direct.size() == 3 * pixels && earlier_.samples > 0;
    // Squared differences weighted as relMSE weighs them: of the direct light between the earlier and the kept
    // frame and between the kept and the last, and of the rest between the kept and the last.
    double direct_before = 0.0, direct_after = 0.0, rest_after = 0.0;
    for (std::size_t p = 0; p < pixels; ++p)
      for (std::size_t c = 0; c < 3; ++c) {
        const double x = last[4 * p + c], weight = 1.0 / (x * x + 0.01);
        const double d = double(kept_.combined[4 * p + c]) - x;
        if (!direct_apart) {
          rest_after += d * d * weight;
          continue;
        }
        const double d_direct = double(kept_.direct[3 * p + c]) - double(last_direct[3 * p + c]);
        direct_after += d_direct * d_direct * weight;
        rest_after += (d - d_direct) * (d - d_direct) * weight;
        if (rate_known) {
          const double before = double(earlier_.direct[3 * p + c]) - double(kept_.direct[3 * p + c]);
          direct_before += before * before * weight;
        }
      }
    const double later = double(samples_done) / double(kept_.samples);
    const double measured =
        rate_known ? convergence_rate(direct_before / direct_after, earlier_.samples, kept_.samples, samples_done)
                   : 0.0;
    const double rate = measured > 0.0 ? (kept_.rate > 0.0 ? 0.5 * (measured + kept_.rate) : measured) : 1.0;
    const double values = double(3 * pixels);
    const double direct = direct_after / (std::pow(later, rate) - 1.0) / values;
    return {{float(direct + rest_after / (later - 1.0) / values), float(direct), float(rate)}, measured};
  }

  Kept earlier_, kept_;  // the last two checkpoints up to half-way, the later one kept_
  Noise checkpoint_noise_;
  int checkpoint_samples_ = 0;
};

}  // namespace bounce
