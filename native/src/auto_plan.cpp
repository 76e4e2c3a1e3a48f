#include "auto_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "frame_plan.h"
#include "settings.h"

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

// An effect's share of the image: of its mean, and pixel by pixel (the root of its error weight: the root mean
// square over the image of its part of each block of 4x4 pixels). The open ground's second bounce is 0.9 % of the
// mean but lights the shadows, where it is a larger part: leaving it out cost 1.6 % pixel by pixel against Cycles
// (relMSE 0.00026 of its 4x4 blocks), more than two bounces' whole error at 4 samples (0.00014). An effect is
// below a threshold only where both are.
struct EffectShare {
  double mean = 0.0, per_pixel = 0.0;

  EffectShare(double mean_share, double error_weight) : mean(mean_share), per_pixel(std::sqrt(error_weight)) {}
  bool below(double threshold) const { return mean < threshold && per_pixel < threshold; }
  // The mean, and the share pixel by pixel where that is what keeps the effect.
  std::string words(double threshold) const {
    return percent(mean) +
           (mean < threshold && per_pixel >= threshold ? " (" + percent(per_pixel) + " pixel by pixel)" : "");
  }
};

// How a plan's VPLs are named: SSVP's are its first bounce's.
const char* vpl_words(int32_t method) { return method == BOUNCE_METHOD_SSVP ? " first-bounce VPLs" : " VPLs"; }

std::string join(const std::vector<std::string>& parts, const char* separator) {
  std::string out;
  for (const std::string& part : parts) out += (out.empty() ? "" : separator) + part;
  return out;
}

// The method that renders Auto's bounces. Topology: ray-traced direct light and VPLs traced from every source,
// with indirect shadows by visibility clusters and gates; at equal wall time the lowest combined error on 8 of the
// 9 scenes of `scripts/benchmark --suite budget-time` (README, Auto), and the only method that keeps a closed
// room dark (the two rooms: 0.013 where Screen-Space VPL Propagation, whose shadows come from paraboloid maps of
// a few clusters, is at 0.52 and direct light alone at 0.20).
constexpr int32_t kIndirectMethod = BOUNCE_METHOD_TOPOLOGY;
constexpr const char* kIndirectMethodName = "Topology (VPLs with indirect shadows)";

double sample_budget(const BounceSettings& settings) {
  double budget = settings.sample_budget;
  if (settings.time_limit > 0.0f) {
    const double share = 1000.0 * settings.time_limit / std::max(settings.samples, 1);
    budget = budget > 0.0 ? std::min(budget, share) : share;
  }
  return budget;
}

// Fits `out` (a plan with VPLs, or DIRECT) to `budget` ms per sample: the VPLs that fill it, else one bounce
// fewer; where Topology does not fit with one bounce, Screen-Space VPL Propagation with the planned bounces (whose
// cost grows with the GPU where Topology's grows with the CPU cores), and its bounces in turn, down to direct
// light. The budget is a target, not a ceiling: where direct light falls further below it than the cheapest plan
// with a bounce (at its fewest VPLs) rises above it, that plan renders. A plan not measured yet renders at its
// fewest VPLs. Returns the sentence that says how.
std::string fit_budget(BounceSettings& out, double budget, const CostModel& costs, int64_t pixels,
                       double& estimated_ms) {
  const std::string head = "Budget " + milliseconds(budget) + " per sample";
  const int32_t planned_bounces = out.bounces;
  std::vector<std::string> parts;
  std::optional<BounceSettings> cheapest_over;  // the cheapest plan with a bounce that did not fit
  double cheapest_over_ms = 0.0;
  while (true) {
    const std::optional<SampleCost> cost = costs.predict(out.method, out.bounces, pixels);
    if (!cost) {
      // Measured at its fewest VPLs: the cheapest frame that teaches the model, the nearest the budget can be.
      if (const std::optional<VplSetting> vpl = vpl_setting(out.method))
        out.*vpl->member = int32_t(soft_range(vpl->name).min);
      parts.push_back("cost not measured yet");
      return head + ": " + join(parts, ", ");
    }
    const std::optional<VplSetting> vpl = vpl_setting(out.method);
    if (!vpl) {
      estimated_ms = cost->at(0);
      parts.push_back("direct light " + milliseconds(estimated_ms));
      if (cheapest_over && cheapest_over_ms / budget < budget / estimated_ms) {
        out = *cheapest_over;
        estimated_ms = cheapest_over_ms;
        parts.push_back("nearer the budget: " +
                        std::string(out.method == BOUNCE_METHOD_SSVP ? "Screen-Space VPL Propagation" : "Topology") +
                        (out.bounces >= 2 ? " with two bounces at " : " with one bounce at ") +
                        std::to_string(out.*vpl_setting(out.method)->member) + vpl_words(out.method) + ", " +
                        milliseconds(estimated_ms));
      }
      return head + ": " + join(parts, ", ");
    }
    // The VPLs a budget may buy: the setting's soft range, so that every plan stays one the user could have set.
    const SoftRange range = soft_range(vpl->name);
    int32_t& vpl_count = out.*vpl->member;
    const double vpls = cost->per_vpl_ms > 0.0     ? (budget - cost->fixed_ms) / cost->per_vpl_ms
                        : cost->fixed_ms <= budget ? double(vpl_count)
                                                   : 0.0;
    if (vpls >= range.min) {
      vpl_count = int32_t(std::min(vpls, range.max));
      estimated_ms = cost->at(vpl_count);
      parts.push_back(std::to_string(vpl_count) + vpl_words(out.method) + ", " + milliseconds(estimated_ms));
      return head + ": " + join(parts, ", ");
    }
    const double fewest_ms = cost->at(int(range.min));
    if (!cheapest_over || fewest_ms < cheapest_over_ms) {
      cheapest_over = out;
      (*cheapest_over).*vpl->member = int32_t(range.min);
      cheapest_over_ms = fewest_ms;
    }
    const std::string fewest = " (" + milliseconds(fewest_ms) + ")";
    if (out.bounces >= 2) {
      parts.push_back("second bounce dropped" + fewest);
      out.bounces = 1;
    } else if (out.method == BOUNCE_METHOD_TOPOLOGY) {
      parts.push_back("Topology too slow" + fewest + ", Screen-Space VPL Propagation instead");
      out.method = BOUNCE_METHOD_SSVP;
      out.bounces = planned_bounces;
    } else {
      parts.push_back("bounces dropped" + fewest);
      out.method = BOUNCE_METHOD_DIRECT;
    }
  }
}

}  // namespace

double bounce_bias(const BounceSettings& settings) {
  // Measured by `scripts/benchmark --suite budget-time --quick --reference-samples 1024` against Cycles (README,
  // Auto; the report's "Bias classes"): per scene, the bias of a method's bounces (from their error at 1 and 4
  // samples as B + V / N) over their error weight, and the median over the suite's 12 scenes. The direct light's
  // bias, ray traced or from shadow maps, has a median of 0 in the same measure, so it is not counted. SSVP's and
  // FLC's classes keep an older run's value where the latest median put fewer of their estimates within a factor
  // of 2 of the measured error.
  switch (settings.method) {
    case BOUNCE_METHOD_TOPOLOGY:
      // With Ray Checks, two bounces: 0.024 (the rule alone had 0.057); with 0.11, the estimate of Auto's render
      // was within a factor of 2 of the measured error on 8 of the 12 scenes, 5 times too high on the Cornell boxes.
      return 0.024;
    case BOUNCE_METHOD_SSVP:
      // With Ray Checks and the second bounce's near field (bd7c36b): 0.018, which puts SSVP's estimates within a
      // factor of 2 of the measured error on 9 of the 12 scenes, where 0.29 (its maps alone) put 8.
      return 0.018;
    case BOUNCE_METHOD_FLC:
      // Indirect Shadows: the topology's clusters and gates, with Ray Checks (latest median 0.16, from 0 to 2.4).
      // Without them light passes every wall: 1.28, from 0.05 (the Cornell box) to 26 (two rooms).
      return settings.flc_visibility ? 0.11 : 1.3;
    default:
      return 0.0;
  }
}

double accepted_bias(const BounceSettings& settings, const cpu::SceneAnalysis& analysis) {
  const double bias = bounce_bias(settings);
  const int bounces = plan_frame(settings).bounces;  // the analysis weighs two
  double error = bounces >= 2
                     ? bias * analysis.error_weight_bounces
                     : (bounces == 1 ? bias : 1.0) * analysis.error_weight_first + analysis.error_weight_second;
  const int32_t source_lights[cpu::kLightSourceCount] = {1, settings.world_lights, settings.emission_lights};
  for (int c = 0; c < cpu::kLightSourceCount; ++c)
    if (source_lights[c] == 0) error += analysis.error_weight_source[c];
  return error;
}

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
    const EffectShare share(analysis.share(analysis.direct[c] + analysis.first_bounce[c] + second),
                            analysis.error_weight_source[c]);
    if (!(share.mean > 0.0)) continue;
    const bool kept = !share.below(threshold) || !source_lights[c];
    if (!kept) *source_lights[c] = 0;
    std::vector<std::string>& list = kept ? lit : skipped;
    list.push_back((list.empty() ? kSourceNames[c] : kSourceLowerNames[c]) + (" " + share.words(threshold)));
  }
  std::vector<std::string> sentences;
  if (!lit.empty()) sentences.push_back(join(lit, ", ") + " of the light");
  if (!skipped.empty()) sentences.push_back(join(skipped, ", ") + ": skipped" + below);
  if (lit.empty() && skipped.empty()) sentences.push_back("No light reaches what the camera sees");

  const EffectShare first(analysis.share(first_total), analysis.error_weight_first);
  const EffectShare second(analysis.share(analysis.second_bounce), analysis.error_weight_second);
  if (first.below(threshold)) {
    out.method = BOUNCE_METHOD_DIRECT;
    const EffectShare bounces(first.mean + second.mean, analysis.error_weight_bounces);
    sentences.push_back("Bounces " + bounces.words(threshold) + ": skipped" + below);
  } else {
    out.method = kIndirectMethod;
    out.bounces = second.below(threshold) ? 1 : 2;
    if (out.bounces == 2) {
      sentences.push_back("First bounce " + first.words(threshold) + " and second " + second.words(threshold) + ": " +
                          kIndirectMethodName);
    } else {
      sentences.push_back("First bounce " + first.words(threshold) + ": " + kIndirectMethodName);
      sentences.push_back("Second bounce " + second.words(threshold) + ": skipped" + below);
    }
  }
  // Time saved by what was skipped, where the model has measured the fuller plan.
  if (const auto vpl = vpl_setting(out.method); vpl && out.bounces == 1 && second.below(threshold)) {
    const auto one = costs.predict(out.method, 1, pixels), two = costs.predict(out.method, 2, pixels);
    const int32_t vpls = out.*vpl->member;
    if (one && two) sentences.back() += ", saving " + milliseconds(two->at(vpls) - one->at(vpls)) + " a sample";
  }
  plan.budget_ms = sample_budget(settings);
  if (plan.budget_ms > 0.0) sentences.push_back(fit_budget(out, plan.budget_ms, costs, pixels, plan.estimated_ms));
  plan.summary = join(sentences, ". ") + ".";
  plan.bias_relmse = accepted_bias(out, analysis);
  BounceLightShares& shares = plan.shares;
  for (int c = 0; c < cpu::kLightSourceCount; ++c) {
    shares.direct[c] = float(analysis.share(analysis.direct[c]));
    shares.first_bounce[c] = float(analysis.share(analysis.first_bounce[c]));
  }
  shares.second_bounce = float(second.mean);
  shares.emission_seen = float(analysis.share(analysis.emission_seen));
  shares.background_seen = float(analysis.share(analysis.background_seen));
  shares.mean_albedo = float(analysis.mean_albedo);
  shares.openness = float(analysis.openness);
  shares.analysis_ms = float(analysis.milliseconds);
  return plan;
}

}  // namespace bounce
