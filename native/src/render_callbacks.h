// What a render reports back to its engine while it runs.
#pragma once

#include <functional>
#include <memory>

#include "frame.h"

namespace bounce {

struct RenderCallbacks {
  std::function<bool()> cancelled;
  std::function<void(std::shared_ptr<Frame>)> publish;  // progressive frames and the final one
  std::function<void(int samples_done, float progress)> progress;
  // A step before sampling (precomputation) and its share of the progress bar so far; "" when sampling starts.
  std::function<void(const char* stage, float progress)> status;
};

}  // namespace bounce
