// A finished (or progressively refined) image: every AOV as interleaved floats, rows bottom first.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "bounce/bounce.h"

namespace bounce {

// bounce_method_aovs: the AOVs `method` writes.
inline uint32_t method_aovs(int32_t method) {
  uint32_t aovs = 0;
  for (int aov : {BOUNCE_AOV_COMBINED, BOUNCE_AOV_DIRECT, BOUNCE_AOV_EMISSION, BOUNCE_AOV_ALBEDO, BOUNCE_AOV_NORMAL,
                  BOUNCE_AOV_DEPTH})
    aovs |= 1u << aov;
  if (method == BOUNCE_METHOD_FLC || method == BOUNCE_METHOD_SSVP)
    aovs |= (1u << BOUNCE_AOV_INDIRECT) | (1u << BOUNCE_AOV_VPLS);
  if (method == BOUNCE_METHOD_SSVP || method == BOUNCE_METHOD_TOPOLOGY) aovs |= 1u << BOUNCE_AOV_SECOND_BOUNCE;
  if (method == BOUNCE_METHOD_TOPOLOGY) aovs |= (1u << BOUNCE_AOV_INDIRECT) | (1u << BOUNCE_AOV_TOPOLOGY);
  if (method == BOUNCE_METHOD_AUTO) aovs |= (1u << BOUNCE_AOV_INDIRECT) | (1u << BOUNCE_AOV_SECOND_BOUNCE);
  return aovs;
}

struct Frame {
  int width = 0, height = 0;
  uint32_t held = 0;  // bits 1 << aov of the AOVs allocated (method_aovs)
  std::array<std::vector<float>, BOUNCE_AOV_COUNT> aovs;
  BounceFrameInfo info = [] {
    BounceFrameInfo unknown_error{};
    unknown_error.noise_relmse = -1.0f;  // until a render estimates it
    unknown_error.noise_direct_rate = 1.0f;
    unknown_error.bias_relmse = -1.0f;  // until the renderer weighs the frame's settings
    return unknown_error;
  }();

  void allocate(int w, int h, uint32_t aov_bits) {
    width = w;
    height = h;
    held = aov_bits;
    info.aovs = aov_bits;
    for (int aov = 0; aov < BOUNCE_AOV_COUNT; ++aov)
      if (holds(aov)) aovs[aov].assign(std::size_t(w) * h * bounce_aov_channels(aov), 0.0f);
  }
  bool holds(int aov) const { return (held >> aov) & 1u; }
  // Frees every AOV but those of `aov_bits`: a partial frame holds what the noise estimate reads once Ray Checks' clamp
  // has read its Indirect pass.
  void keep(uint32_t aov_bits) {
    for (int aov = 0; aov < BOUNCE_AOV_COUNT; ++aov)
      if (!((aov_bits >> aov) & 1u)) std::vector<float>().swap(aovs[aov]);
    held &= aov_bits;
    info.aovs = held;
  }
  // Scales the AOVs that average their samples (all but Depth, the nearest of them).
  void scale(float factor) {
    for (int aov = 0; aov < BOUNCE_AOV_COUNT; ++aov)
      if (aov != BOUNCE_AOV_DEPTH)
        for (float& value : aovs[aov]) value *= factor;
  }

  // Where signed corrections (Ray Checks, in Forward Light Cuts, SSVP and the Topology method) leave a pixel's mean
  // Indirect below zero (the light they took away was not there), it shows none: the deficit goes back into
  // Indirect and Combined, on the mean of the samples (clamped per sample, the image would keep the rule's excess
  // wherever a check found one). With the Second Bounce held, each bounce is clamped on its own, so that Indirect
  // holds the Second Bounce and a one-bounce render's Indirect is the first bounce's here.
  void clamp_negative_indirect() {
    if (!holds(BOUNCE_AOV_INDIRECT)) return;
    const std::size_t indirect_channels = std::size_t(bounce_aov_channels(BOUNCE_AOV_INDIRECT));
    const std::size_t combined_channels = std::size_t(bounce_aov_channels(BOUNCE_AOV_COMBINED));
    const std::size_t second_channels = std::size_t(bounce_aov_channels(BOUNCE_AOV_SECOND_BOUNCE));
    const bool second_held = holds(BOUNCE_AOV_SECOND_BOUNCE);
    for (std::size_t i = 0; i < std::size_t(width) * std::size_t(height); ++i)
      for (std::size_t c = 0; c < 3; ++c) {
        float& indirect = aovs[BOUNCE_AOV_INDIRECT][indirect_channels * i + c];
        float first = indirect, second = 0.0f;
        if (second_held) {
          float& held_second = aovs[BOUNCE_AOV_SECOND_BOUNCE][second_channels * i + c];
          first -= held_second;
          held_second = second = std::max(held_second, 0.0f);
        }
        const float clamped = std::max(first, 0.0f) + second;
        if (clamped == indirect) continue;
        if (holds(BOUNCE_AOV_COMBINED)) aovs[BOUNCE_AOV_COMBINED][combined_channels * i + c] += clamped - indirect;
        indirect = clamped;
      }
  }
  // Sets every AOV value of a pixel whose channels are not all finite to zero; returns how many pixels had one
  // (counted once however many of their AOVs did: the count is of the image's pixels).
  uint64_t zero_nonfinite() {
    std::vector<bool> bad(std::size_t(width) * height, false);
    for (int aov = 0; aov < BOUNCE_AOV_COUNT; ++aov) {
      if (!holds(aov)) continue;
      const std::size_t channels = std::size_t(bounce_aov_channels(aov));
      for (std::size_t i = 0; i < bad.size(); ++i) {
        float* value = aovs[aov].data() + channels * i;
        bool finite = true;
        for (std::size_t c = 0; c < channels; ++c) finite = finite && std::isfinite(value[c]);
        if (finite) continue;
        for (std::size_t c = 0; c < channels; ++c) value[c] = 0.0f;
        bad[i] = true;
      }
    }
    return uint64_t(std::count(bad.begin(), bad.end(), true));
  }
};

}  // namespace bounce
