// A finished (or progressively refined) image: every AOV as interleaved floats, rows bottom first.
#pragma once

#include <array>
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
  return aovs;
}

struct Frame {
  int width = 0, height = 0;
  uint32_t held = 0;  // bits 1 << aov of the AOVs allocated (method_aovs)
  std::array<std::vector<float>, BOUNCE_AOV_COUNT> aovs;
  BounceFrameInfo info{};

  void allocate(int w, int h, uint32_t aov_bits) {
    width = w;
    height = h;
    held = aov_bits;
    for (int aov = 0; aov < BOUNCE_AOV_COUNT; ++aov)
      if (holds(aov)) aovs[aov].assign(std::size_t(w) * h * bounce_aov_channels(aov), 0.0f);
  }
  bool holds(int aov) const { return (held >> aov) & 1u; }
};

}  // namespace bounce
