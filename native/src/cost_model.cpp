#include "cost_model.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>

namespace bounce {
namespace {

constexpr const char* kHeader = "bounce cost model 1";

struct Registry {
  std::mutex mutex;
  std::map<std::string, std::unique_ptr<CostModel>> models;
  std::filesystem::path directory;
};
Registry& registry() {
  static Registry r;
  return r;
}

std::filesystem::path file_of(const std::filesystem::path& directory, const std::string& device) {
  if (directory.empty()) return {};
  uint64_t hash = 1469598103934665603ull;  // FNV-1a
  for (unsigned char c : device) hash = (hash ^ c) * 1099511628211ull;
  char name[48];
  std::snprintf(name, sizeof name, "cost-model-%016llx.txt", static_cast<unsigned long long>(hash));
  return directory / name;
}

// Bounces matter to SSVP only (1 or 2) and Topology; the others have one cost per method.
std::pair<int32_t, int32_t> key_of(int32_t method, int32_t bounces) {
  if (method == BOUNCE_METHOD_SSVP) return {method, std::min(bounces, 2)};
  if (method == BOUNCE_METHOD_TOPOLOGY) return {method, bounces};
  return {method, 0};
}

}  // namespace

CostModel& CostModel::of_device(const std::string& device) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  std::unique_ptr<CostModel>& model = r.models[device];
  if (!model) {
    model = std::make_unique<CostModel>(device);
    model->keep_at(file_of(r.directory, device));
  }
  return *model;
}

void CostModel::keep_in(const std::filesystem::path& directory) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  r.directory = directory;
  for (auto& [device, model] : r.models) model->keep_at(file_of(directory, device));
}

void CostModel::keep_at(const std::filesystem::path& file) {
  {
    const std::lock_guard lock(mutex_);
    if (file == file_) return;
    file_ = file;
  }
  if (!file.empty()) read(file);
}

void CostModel::observe(const BounceSettings& settings, int64_t pixels, double sample_ms, double vpl_share) {
  if (pixels <= 0 || !(sample_ms > 0.0) || !std::isfinite(sample_ms)) return;
  const double share = std::isfinite(vpl_share) ? std::clamp(vpl_share, 0.0, 1.0) : 0.0;
  std::filesystem::path file;
  {
    const std::lock_guard lock(mutex_);
    std::deque<Observation>& seen = costs_[key_of(settings.method, settings.bounces)];
    const std::optional<VplSetting> vpls = vpl_setting(settings.method);
    seen.push_back({double(vpls ? std::max(settings.*vpls->member, 1) : 1), sample_ms / double(pixels), share});
    if (seen.size() > kKept) seen.pop_front();
    file = file_;
  }
  if (!file.empty()) write(file);
}

std::size_t CostModel::frames() const {
  const std::lock_guard lock(mutex_);
  std::size_t count = 0;
  for (const auto& [key, seen] : costs_) count += seen.size();
  return count;
}

bool CostModel::write(const std::filesystem::path& file) const {
  std::ostringstream text;
  text.precision(17);
  {
    const std::lock_guard lock(mutex_);
    text << kHeader << "\ndevice " << device_ << "\n";
    for (const auto& [key, seen] : costs_)
      for (const Observation& o : seen)
        text << key.first << ' ' << key.second << ' ' << o.vpls << ' ' << o.ms_per_pixel << ' ' << o.vpl_share << '\n';
  }
  // Written beside, under a name no other writer uses (another process, or another engine of this one finishing
  // a render at the same time), and renamed over: a reader sees the old model or the new, whole.
  static std::atomic<uint64_t> writes{0};
  std::error_code error;
  std::filesystem::create_directories(file.parent_path(), error);
  std::filesystem::path partial = file;
  partial += "." + std::to_string(::getpid()) + "-" + std::to_string(writes.fetch_add(1)) + ".partial";
  {
    std::ofstream out(partial, std::ios::trunc);
    out << text.str();
    if (!out.flush()) return false;
  }
  std::filesystem::rename(partial, file, error);
  if (!error) return true;
  std::filesystem::remove(partial, error);
  return false;
}

bool CostModel::read(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string header, device;
  if (!std::getline(in, header) || header != kHeader || !std::getline(in, device) || device != "device " + device_)
    return false;
  std::map<std::pair<int32_t, int32_t>, std::deque<Observation>> read;
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    int32_t method = 0, bounces = 0;
    Observation o{};
    if (!(fields >> method >> bounces >> o.vpls >> o.ms_per_pixel >> o.vpl_share)) continue;
    if (!(o.vpls >= 1.0 && std::isfinite(o.vpls) && o.ms_per_pixel > 0.0 && std::isfinite(o.ms_per_pixel) &&
          o.vpl_share >= 0.0 && o.vpl_share <= 1.0))
      continue;  // a damaged line is not a measurement
    read[key_of(method, bounces)].push_back(o);
  }
  const std::lock_guard lock(mutex_);
  for (auto& [key, seen] : read) {
    std::deque<Observation>& kept = costs_[key];
    kept.insert(kept.begin(), seen.begin(), seen.end());
    while (kept.size() > kKept) kept.pop_front();
  }
  return true;
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
