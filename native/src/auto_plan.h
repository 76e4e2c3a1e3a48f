// Auto: the explicit method and settings a frame renders with, chosen from what the scene's light is made of
// (cpu::SceneAnalysis), and the words that tell the user what was chosen and why.
#pragma once

#include <string>

#include "bounce/bounce.h"
#include "cost_model.h"
#include "cpu/scene_analysis.h"

namespace bounce {

struct AutoPlan {
  BounceSettings settings;  // method no longer AUTO
  BounceLightShares shares{};
  double budget_ms = 0.0;     // per sample: settings.sample_budget, or Time Limit / Samples if less; 0 none
  double estimated_ms = 0.0;  // the cost model's estimate of a sample of the plan; 0 before one was measured
  std::string summary;        // e.g. "Lamps 61 %, world 38 % of the light. Emission 0.4 %: skipped (below 1.0 %).
                              // First bounce 27 %: Screen-Space VPL Propagation. Second bounce 0.6 %: skipped ..."
  // The error the plan accepts (accepted_bias); -1 where unknown.
  double bias_relmse = -1.0;
};

// A method's bias class: the squared relative error per pixel its converged bounces keep against the Cycles
// oracle (their relMSE over their error weight); 0 for a method without bounces.
double bounce_bias(const BounceSettings& settings);

// The error a render with `settings` (an explicit method) accepts, as relMSE, which more samples do not remove:
// each effect it leaves out (bounces, light source classes) by its error weight in `analysis`, each one it
// simulates by its error weight times the method's bias class.
double accepted_bias(const BounceSettings& settings, const cpu::SceneAnalysis& analysis);

// An effect (a light source class, a bounce) whose estimated share of the image is below settings.auto_threshold,
// in the mean and pixel by pixel (the root of its error weight), is not simulated: a source class by drawing none of
// its lights (World Directions or Emissive Triangles 0, and so none of its bounces), a bounce by the method's bounce
// count, or by no indirect method at all. With a budget, what remains is fitted to it with `costs` (for `pixels`
// pixels): the first-bounce VPL count that fills it, else one bounce fewer, down to direct light; a plan whose cost is
// not measured yet renders as it is, and its frame teaches the model.
AutoPlan plan_auto(const BounceSettings& settings, const cpu::SceneAnalysis& analysis, const CostModel& costs,
                   int64_t pixels);

}  // namespace bounce
