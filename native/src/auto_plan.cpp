#include "auto_plan.h"

#include <cmath>
#include <cstdio>
#include <vector>

namespace bounce {
namespace {

std::string percent(double share) {
  char text[32];
  std::snprintf(text, sizeof text, share < 0.0995 ? "%.1f %%" : "%.0f %%", 100.0 * share);
  return text;
}

std::string join(const std::vector<std::string>& parts, const char* separator) {
  std::string out;
  for (const std::string& part : parts) out += (out.empty() ? "" : separator) + part;
  return out;
}

}  // namespace

AutoPlan plan_auto(const BounceSettings& settings, const cpu::SceneAnalysis& analysis) {
  AutoPlan plan{settings, {}, ""};
  BounceSettings& out = plan.settings;
  const double threshold = settings.auto_threshold;
  const std::string below = " (below " + percent(threshold) + ")";

  // A source class's share: its direct light, its first bounce and its part of the second (in proportion to its
  // first bounce).
  const double first_total = analysis.first_bounce_total();
  std::vector<std::string> lit, skipped;
  static const char* const kSourceNames[cpu::kLightSourceCount] = {"Lamps", "World", "Emission"};
  static const char* const kSourceLowerNames[cpu::kLightSourceCount] = {"lamps", "world", "emission"};
  int32_t* const source_lights[cpu::kLightSourceCount] = {nullptr, &out.world_lights, &out.emission_lights};
  for (int c = 0; c < cpu::kLightSourceCount; ++c) {
    const double second = first_total > 0.0 ? analysis.second_bounce * analysis.first_bounce[c] / first_total : 0.0;
    const double share = analysis.share(analysis.direct[c] + analysis.first_bounce[c] + second);
    if (!(share > 0.0)) continue;
    if (share >= threshold || !source_lights[c]) {
      lit.push_back(std::string(lit.empty() ? kSourceNames[c] : kSourceLowerNames[c]) + " " + percent(share));
    } else {
      *source_lights[c] = 0;
      skipped.push_back(std::string(skipped.empty() ? kSourceNames[c] : kSourceLowerNames[c]) + " " + percent(share));
    }
  }
  std::vector<std::string> sentences;
  if (!lit.empty()) sentences.push_back(join(lit, ", ") + " of the light");
  if (!skipped.empty()) sentences.push_back(join(skipped, ", ") + ": skipped" + below);
  if (lit.empty() && skipped.empty()) sentences.push_back("No light reaches what the camera sees");

  const double first = analysis.share(first_total), second = analysis.share(analysis.second_bounce);
  if (first < threshold) {
    out.method = BOUNCE_METHOD_DIRECT;
    sentences.push_back("Bounces " + percent(first + second) + ": skipped" + below);
  } else {
    // Screen-Space VPL Propagation: the first bounce within 4 % of Cycles on the Cornell box, Sponza and the sunlit
    // interior, and the best error at equal time of the error budget on two of its four scenes (README, Accuracy).
    out.method = BOUNCE_METHOD_SSVP;
    out.bounces = second >= threshold ? 2 : 1;
    if (out.bounces == 2) {
      sentences.push_back("First bounce " + percent(first) + " and second " + percent(second) +
                          ": Screen-Space VPL Propagation");
    } else {
      sentences.push_back("First bounce " + percent(first) + ": Screen-Space VPL Propagation");
      sentences.push_back("Second bounce " + percent(second) + ": skipped" + below);
    }
  }
  plan.summary = join(sentences, ". ") + ".";
  BounceLightShares& shares = plan.shares;
  for (int c = 0; c < cpu::kLightSourceCount; ++c) {
    shares.direct[c] = float(analysis.share(analysis.direct[c]));
    shares.first_bounce[c] = float(analysis.share(analysis.first_bounce[c]));
  }
  shares.second_bounce = float(second);
  shares.emission_seen = float(analysis.share(analysis.emission_seen));
  shares.background_seen = float(analysis.share(analysis.background_seen));
  shares.mean_albedo = float(analysis.mean_albedo);
  shares.openness = float(analysis.openness);
  shares.analysis_ms = float(analysis.milliseconds);
  return plan;
}

}  // namespace bounce
