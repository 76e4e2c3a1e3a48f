#include "cpu/topology_cache.h"

#include <atomic>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "cpu/random.h"

namespace bounce::cpu {
namespace {

constexpr std::size_t kCachedTopologies = 2;  // the viewport's and an F12 render's, when their settings differ
std::mutex cache_mutex;
std::vector<std::pair<uint64_t, std::shared_ptr<const topology::Topology>>> cache;  // most recent last
std::atomic<uint64_t> builds{0};

std::shared_ptr<const topology::Topology> cached(uint64_t key) {
  std::lock_guard lock(cache_mutex);
  for (auto it = cache.begin(); it != cache.end(); ++it) {
    if (it->first != key) continue;
    auto entry = *it;
    cache.erase(it);
    cache.push_back(entry);
    return entry.second;
  }
  return nullptr;
}

// Stores `value` as the most recent, in place of what `key` held.
void store(uint64_t key, std::shared_ptr<const topology::Topology> value) {
  std::lock_guard lock(cache_mutex);
  std::erase_if(cache, [key](const auto& entry) { return entry.first == key; });
  if (cache.size() >= kCachedTopologies) cache.erase(cache.begin());
  cache.emplace_back(key, std::move(value));
}

}  // namespace

uint64_t topology_builds() { return builds.load(); }

std::shared_ptr<const topology::Topology> TopologyCache::get(const CpuScene& scene, const BounceSettings& settings,
                                                             const RenderCallbacks& callbacks) {
  // One key for both renderers: FLC's topology is the Topology method's with the ray estimates added.
  uint64_t key = mix(scene.geometry_hash() ^ mix(uint64_t(settings.topology_resolution)));
  uint32_t alpha_bits = 0;
  std::memcpy(&alpha_bits, &settings.topology_alpha, sizeof alpha_bits);
  key = mix(key ^ alpha_bits);
  // The cache's first: another renderer may have added the estimates to the one this object holds.
  std::shared_ptr<const topology::Topology> found = cached(key);
  if (!found && topology_ && key == key_) found = topology_;
  if (found && found->occluders_estimated && (found->passages_estimated || !with_passages_)) {
    if (found != topology_) topology_ = std::move(found), key_ = key;
    return topology_;
  }
  std::string stage_text;
  const topology::Progress progress = [&](topology::BuildStage stage, float fraction) {
    stage_text = std::string("Topology: ") + topology::build_stage_name(stage);
    callbacks.status(stage_text.c_str(), 0.5f * fraction);
    return !callbacks.cancelled();
  };
  topology::RayQueries rays{{}, [&scene](glm::vec3 origin, glm::vec3 direction) {
                              const auto hit =
                                  scene.intersect(origin, direction, 0.0f, std::numeric_limits<float>::infinity());
                              return hit ? topology::Occluders::Hit{hit->t, hit->normal} : topology::Occluders::Hit{};
                            }};
  if (with_passages_) rays.clear = [&scene](glm::vec3 from, glm::vec3 to) { return scene.clear_between(from, to); };
  try {
    if (found) {
      topology_ =
          std::make_shared<topology::Topology>(topology::with_ray_estimates(*found, scene.soup(), rays, progress));
    } else {
      topology::Settings topology_settings;
      topology_settings.resolution = settings.topology_resolution;
      topology_settings.alpha = settings.topology_alpha;
      topology_ =
          std::make_shared<topology::Topology>(topology::build(scene.soup(), topology_settings, progress, rays));
      ++builds;
    }
  } catch (const topology::Cancelled&) {
    topology_ = nullptr;
    return nullptr;
  }
  key_ = key;
  store(key, topology_);
  return topology_;
}

}  // namespace bounce::cpu
