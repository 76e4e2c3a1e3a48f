// Auto: the explicit method and settings a frame renders with, chosen from what the scene's light is made of
// (cpu::SceneAnalysis), and the words that tell the user what was chosen and why.
#pragma once

#include <string>

#include "bounce/bounce.h"
#include "cpu/scene_analysis.h"

namespace bounce {

struct AutoPlan {
  BounceSettings settings;  // method no longer AUTO
  BounceLightShares shares{};
  std::string summary;  // e.g. "Lamps 61 %, world 38 % of the light. Emission 0.4 %: skipped (below 1.0 %).
                        // First bounce 27 %: Screen-Space VPL Propagation. Second bounce 0.6 %: skipped ..."
};

// An effect (a light source class, a bounce) whose estimated share of the image is below settings.auto_threshold
// is not simulated: a source class by drawing none of its lights (World Directions or Emissive Triangles 0, and
// so none of its bounces), a bounce by the method's bounce count, or by no indirect method at all.
AutoPlan plan_auto(const BounceSettings& settings, const cpu::SceneAnalysis& analysis);

}  // namespace bounce
