#include "auto_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

namespace bounce {
namespace {

std::string percent(double share) {
  char text[32];
  std::snprintf(text, sizeof text, share < 0.0995 ? "%.1f %%" : "%.0f %%", 100.0 * share);
  return text;
}

std::string milliseconds(double ms) {
  char text[32];
  std::snprintf(text, sizeof text, "%.0f ms", ms);
  return text;
}

std::string join(const std::vector<std::string>& parts, const char* separator) {
  std::string out;
  for (const std::string& part : parts) out += (out.empty() ? "" : separator) + part;
  return out;
}

// The fewest first-bounce VPLs worth a bounce under a budget (SSVP's importance resampling keeps a few per
// cluster), and the most a budget may buy (the setting's soft maximum).
constexpr int kFewestVpls = 16;
constexpr int kMostVpls = 2048;

double sample_budget(const BounceSettings& settings) {
  double budget = settings.sample_budget;
  if (settings.time_limit > 0.0f) {
    const double share = 1000.0 * settings.time_limit / std::max(settings.samples, 1);
    budget = budget > 0.0 ? std::min(budget, share) : share;
  }
  return budget;
}

// Fits `out` (an SSVP or DIRECT plan) into `budget` ms per sample: the first-bounce VPLs that fill it, else one
// bounce fewer, down to direct light. Returns the sentence that says how.
std::string fit_budget(BounceSettings& out, double budget, const CostModel& costs, int64_t pixels,
                       double& estimated_ms) {
  const std::string head = "Budget " + milliseconds(budget) + " per sample";
  std::vector<std::string> parts;
  while (true) {
    const std::optional<SampleCost> cost = costs.predict(out.method, out.bounces, pixels);
    if (!cost) {
      parts.push_back("cost not measured yet");
      return head + ": " + join(parts, ", ");
    }
    if (out.method == BOUNCE_METHOD_DIRECT) {
      estimated_ms = cost->at(0);
      parts.push_back("direct light " + milliseconds(estimated_ms));
      return head + ": " + join(parts, ", ");
    }
    const double vpls = cost->per_vpl_ms > 0.0     ? (budget - cost->fixed_ms) / cost->per_vpl_ms
                        : cost->fixed_ms <= budget ? double(out.ssvp_vpls)
                                                   : 0.0;
    if (vpls >= kFewestVpls) {
      out.ssvp_vpls = int32_t(std::min(vpls, double(kMostVpls)));
      estimated_ms = cost->at(out.ssvp_vpls);
      parts.push_back(std::to_string(out.ssvp_vpls) + " first-bounce VPLs, " + milliseconds(estimated_ms));
      return head + ": " + join(parts, ", ");
    }
    parts.push_back((out.bounces >= 2 ? "second bounce dropped (" : "bounces dropped (") +
                    milliseconds(cost->at(kFewestVpls)) + ")");
    if (out.bounces >= 2)
      out.bounces = 1;
    else
      out.method = BOUNCE_METHOD_DIRECT;
  }
}

}  // namespace

AutoPlan plan_auto(const BounceSettings& settings, const cpu::SceneAnalysis& analysis, const CostModel& costs,
                   int64_t pixels) {
  AutoPlan plan{settings, {}, 0.0, 0.0, ""};
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
  // Time saved by what was skipped, where the model has measured the fuller plan.
  if (out.method == BOUNCE_METHOD_SSVP && out.bounces == 1 && settings.bounces >= 2) {
    const auto one = costs.predict(BOUNCE_METHOD_SSVP, 1, pixels), two = costs.predict(BOUNCE_METHOD_SSVP, 2, pixels);
    if (one && two && second < threshold)
      sentences.back() += ", saving " + milliseconds(two->at(out.ssvp_vpls) - one->at(out.ssvp_vpls)) + " a sample";
  }
  plan.budget_ms = sample_budget(settings);
  if (plan.budget_ms > 0.0) sentences.push_back(fit_budget(out, plan.budget_ms, costs, pixels, plan.estimated_ms));
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
