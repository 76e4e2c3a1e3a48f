#include "cost_model.h"

#include <algorithm>
#include <cmath>

namespace bounce {
namespace {

// Bounces matter to SSVP only (1 or 2) and Topology; the others have one cost per method.
std::pair<int32_t, int32_t> key_of(int32_t method, int32_t bounces) {
  if (method == BOUNCE_METHOD_SSVP) return {method, std::min(bounces, 2)};
  if (method == BOUNCE_METHOD_TOPOLOGY) return {method, bounces};
  return {method, 0};
}

}  // namespace

CostModel& CostModel::shared() {
  static CostModel model;
  return model;
}

void CostModel::observe(const BounceSettings& settings, int64_t pixels, double sample_ms, double vpl_share) {
  if (pixels <= 0 || !(sample_ms > 0.0) || !std::isfinite(sample_ms)) return;
  const double share = std::isfinite(vpl_share) ? std::clamp(vpl_share, 0.0, 1.0) : 0.0;
  const std::lock_guard lock(mutex_);
  std::deque<Observation>& seen = costs_[key_of(settings.method, settings.bounces)];
  const std::optional<VplSetting> vpls = vpl_setting(settings.method);
  seen.push_back({double(vpls ? std::max(settings.*vpls->member, 1) : 1), sample_ms / double(pixels), share});
  if (seen.size() > kKept) seen.pop_front();
}

std::optional<SampleCost> CostModel::predict(int32_t method, int32_t bounces, int64_t pixels) const {
  const std::lock_guard lock(mutex_);
  const auto it = costs_.find(key_of(method, bounces));
  if (it == costs_.end() || it->second.empty()) return std::nullopt;
  const std::deque<Observation>& seen = it->second;
  double x = 0.0, y = 0.0, share = 0.0;  // means
  for (const Observation& o : seen) {
    x += o.vpls / double(seen.size());
    y += o.ms_per_pixel / double(seen.size());
    share += o.vpl_share / double(seen.size());
  }
  double sxx = 0.0, sxy = 0.0;
  for (const Observation& o : seen) {
    sxx += (o.vpls - x) * (o.vpls - x);
    sxy += (o.vpls - x) * (o.ms_per_pixel - y);
  }
  // A line through frames of several VPL counts; else (or if timing noise made it fall) the stage split.
  const double slope = sxx > 0.0 && sxy > 0.0 ? sxy / sxx : share * y / x;
  const double fixed = std::max(y - slope * x, 0.0);
  return SampleCost{fixed * double(pixels), slope * double(pixels)};
}

}  // namespace bounce
