// Auto's cost model: what a progressive sample costs on this machine, learned from the samples this engine has
// rendered (no constant tuned elsewhere). Per method and bounce count, the time per pixel of a sample is a line in
// the method's VPL count (vpl_setting), fitted by least squares to the last frames; while they all had one VPL
// count, the stage timer's share of the VPL stages (tracing or importance sampling, and shading) gives the slope.
// Engines on one device share its model (of_device()): a final render is a new engine on the same machine. With a
// directory to keep them in (keep_in(), bounce_cost_model_directory), models outlive the process: each `blender
// -b` of a farm starts from what the earlier ones on that machine measured, instead of from nothing.
#pragma once

#include <deque>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

#include "bounce/bounce.h"

namespace bounce {

// The setting a method's sample cost grows with: Topology's VPLs (paths times bounces), SSVP's first-bounce VPLs
// (the second bounce's follow them); none for the other methods. `name` is its row in settings.def.
struct VplSetting {
  int32_t BounceSettings::*member;
  const char* name;
};
inline std::optional<VplSetting> vpl_setting(int32_t method) {
  if (method == BOUNCE_METHOD_TOPOLOGY) return VplSetting{&BounceSettings::topology_vpls, "topology_vpls"};
  if (method == BOUNCE_METHOD_SSVP) return VplSetting{&BounceSettings::ssvp_vpls, "ssvp_vpls"};
  return std::nullopt;
}

struct SampleCost {
  double fixed_ms = 0.0;    // what does not depend on the VPL count: G-buffer, shadows, direct light, clustering
  double per_vpl_ms = 0.0;  // per VPL of vpl_setting
  double at(int vpls) const { return fixed_ms + per_vpl_ms * vpls; }
};

class CostModel {
 public:
  explicit CostModel(std::string device = "") : device_(std::move(device)) {}
  // The model of `device` (the GL renderer and the CPU threads: what a sample's cost depends on), made on first
  // use, from its file when a directory is set.
  static CostModel& of_device(const std::string& device);
  // Where every device's model is kept, a file each (cost-model-HASH.txt, the device's name inside): read when a
  // model is made or the directory set, written after each observed frame. Empty: kept in memory only (the
  // default). A file that cannot be read or written is ignored: a render never fails for its cost model.
  static void keep_in(const std::filesystem::path& directory);

  // A rendered frame of `settings` at `pixels` pixels whose samples took `sample_ms` each on average, of which
  // the share `vpl_share` was spent on work proportional to its VPL count (vpl_setting).
  void observe(const BounceSettings& settings, int64_t pixels, double sample_ms, double vpl_share);
  // The cost of a sample of `method` with `bounces` at `pixels` pixels; none before a frame of it was observed.
  std::optional<SampleCost> predict(int32_t method, int32_t bounces, int64_t pixels) const;
  std::size_t frames() const;  // the frames it holds, observed here or read from its file

  // Its frames to `file` as text (a header, the device, a line per frame); the file's frames, read back, come
  // before the ones observed here. Both false when the file is not there, not a model of `device_`, or not
  // writable.
  bool write(const std::filesystem::path& file) const;
  bool read(const std::filesystem::path& file);

 private:
  // Where it is kept from now on (empty: nowhere); reads that file when it is another.
  void keep_at(const std::filesystem::path& file);
  struct Observation {
    double vpls, ms_per_pixel, vpl_share;
  };
  static constexpr std::size_t kKept = 8;  // frames per plan: the model follows a scene that changed
  std::string device_;
  mutable std::mutex mutex_;
  std::map<std::pair<int32_t, int32_t>, std::deque<Observation>> costs_;
  std::filesystem::path file_;  // where it is kept; empty: nowhere
};

}  // namespace bounce
