// A finished (or progressively refined) image: every AOV as interleaved floats, rows bottom first.
#pragma once

#include <array>
#include <vector>

#include "bounce/bounce.h"

namespace bounce {

struct Frame {
  int width = 0, height = 0;
  std::array<std::vector<float>, BOUNCE_AOV_COUNT> aovs;
  BounceFrameInfo info{};

  void allocate(int w, int h) {
    width = w;
    height = h;
    for (int aov = 0; aov < BOUNCE_AOV_COUNT; ++aov)
      aovs[aov].assign(std::size_t(w) * h * bounce_aov_channels(aov), 0.0f);
  }
};

}  // namespace bounce
