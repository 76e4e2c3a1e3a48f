// Virtual point lights traced from every light with Embree (Instant Radiosity, Keller 1997; Noel and Biri 2014,
// Sec. V and Fig. 8): paths leave the lights in proportion to their power, and each diffuse hit leaves a VPL
// carrying the path's power reflected there.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "bounce/bounce.h"
#include "cpu/box_grid.h"
#include "cpu/cpu_scene.h"
#include "scene_lights.h"

namespace bounce::cpu {

struct Vpl {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f};    // unit, on the side the light arrived from: the VPL lights that half-space
  glm::vec3 power{0.0f};     // W per channel leaving the VPL (albedo included), spread as cos / pi
  uint32_t bounce = 1;       // 1: lit straight by a lamp
  uint32_t light = 0;        // the index of the light its path left
  glm::vec2 emission{0.0f};  // the point of the light's emission square its path left from (EmissionGuide)
  // The area of the surface it stands for (a GL method's RSM texels), which caps its geometry term at pi / area in
  // UnseenFirstBounce (cpu/near_field.h), as vpl_irradiance in shaders/ssvp/ssvp_common.glsl caps it. 0: no cap
  // (the Topology method's paths). cpu::vpl_irradiance, whose callers have no area, leaves it out.
  float area = 0.0f;
};

// Where a light's paths leave from, guided toward where their light reached the view: a sun's paths leave a disk
// the size of the scene, and a few percent of them enter a room through its window, so resampling the candidates
// (resample) kept the room's light in a few heavy VPLs and 16 samples of a sunlit room gave 0.86 of its indirect
// light (0.92 at 64). A piecewise-constant density over the square of emit()'s first two numbers (a sun's disk by
// area, a point or spot light's directions, an area light's cosine lobe), learned from the importance of the
// light's earlier candidates, and mixed with a uniform share so no path is left out: each path's power is divided
// by its density, so the VPLs stay unbiased however the guide learned (adaptive importance sampling). A guide
// that has learned nothing is uniform.
class EmissionGuide {
 public:
  static constexpr int kCellsPerSide = 32;
  static constexpr double kUniformShare = 0.25;

  // Adds a path's importance to the cell of its emission point.
  void learn(glm::vec2 emission, float importance);
  // Rebuilds the density from what was learned.
  void update();
  bool uniform() const { return cdf_.empty(); }
  // The emission point for `pick` (choosing the cell) and `within` (the point in it), both uniform in [0, 1), and
  // its density over the square (1: uniform).
  struct Sample {
    glm::vec2 emission;
    float density;
  };
  Sample sample(float pick, glm::vec2 within) const;

 private:
  std::vector<double> learned_ = std::vector<double>(kCellsPerSide * kCellsPerSide, 0.0);
  std::vector<double> cdf_;  // cumulative cell probabilities from 0 (find_in_cdf); empty when uniform
};

// How a sample's lights are listed (SceneLights): the lamps, the world's directions, then the emitters.
struct LightKinds {
  std::size_t lamps = 0, world = 0;
};

// Where the world's paths leave from, guided toward where earlier paths' light reached the view. The world's
// directions change from sample to sample (SceneLights), so a density over one direction's disk (EmissionGuide)
// would not carry over; where their light landed does. Under a sky seen through a window, about 1 in 10 of the
// sky's paths lit the view. A grid over the scene's bounds holds the importance of the world's paths at their first
// hits; a guided path picks a cell by it and a uniform point in the cell, and leaves its direction's disk where that
// point projects. Its density over the disk is the sum, over the cells its line crosses, of the cell's probability
// times the length of line inside the cell over the cell's volume (the density of a uniform point in a box,
// projected), mixed with a uniform share: each path's power is divided by it, so the VPLs stay unbiased however
// the guide learned (adaptive importance sampling). A guide that has learned nothing is uniform.
class LandingGuide {
 public:
  static constexpr int kCellsPerSide = 32;  // along the bounds' longest side
  static constexpr double kUniformShare = 0.25;

  LandingGuide() = default;
  // A guide over the box from lo to hi, which lies within the disks its paths leave from.
  LandingGuide(glm::vec3 lo, glm::vec3 hi);
  // Adds the importance of the world's paths among `candidates` (trace_vpls' order) to the cells of their first
  // hits.
  void learn(std::span<const Vpl> candidates, std::span<const float> importance, LightKinds kinds);
  // Rebuilds the cells' probabilities from what was learned.
  void update();
  bool uniform() const { return cdf_.empty(); }
  // Where a path leaves the disk of `radius` about `disk_centre` that faces unit `direction` (the path's): at
  // `uniform_origin`, a uniform point of the disk, when `choice` falls in the uniform share, else where the point
  // that `pick` (choosing the cell) and `within` (the point in it) draw projects; all uniform in [0, 1). Its density
  // over the disk is relative to the uniform one's; 0 where the point falls off the disk (the path carries no light).
  struct Origin {
    glm::vec3 point;
    float density;
  };
  Origin origin(glm::vec3 uniform_origin, glm::vec3 disk_centre, glm::vec3 direction, float radius, float choice,
                float pick, glm::vec3 within) const;

 private:
  float density(glm::vec3 origin, glm::vec3 direction, float disk_area) const;

  BoxGrid grid_;
  std::vector<double> learned_;
  std::vector<double> cdf_;  // cumulative cell probabilities from 0 (find_in_cdf); empty when uniform
};

struct VplOptions {
  int paths = 1024;  // paths traced from the lights, all of them
  int bounces = 1;   // diffuse hits per path, each leaving a VPL
  uint64_t seed = 0;
  std::span<const EmissionGuide> guides;      // per light, by index; the lights past its end emit uniformly
  std::span<const double> path_weights;       // per light, what the paths are shared out by; empty: the lights' power
  LightKinds kinds;                           // which lights are the world's directions, guided by world_guide
  const LandingGuide* world_guide = nullptr;  // none: they emit uniformly
  // The world's table: each of the world's paths draws a direction of its own from it, stratified over the
  // sample's world paths, instead of leaving along one of the sample's few world directions (World Directions, 4
  // by default), whose choice swung the whole image's first bounce under a sky from sample to sample (Sponza under
  // forest.exr at 16 samples: 0.82-1.37 of Cycles' over six seeds). None: each path takes its world light's.
  const SceneLights* world_table = nullptr;
};

// Paths are shared out among the lights in proportion to their weights (light_of_paths), each carrying its light's
// power over its light's path count (the world's paths with a table: the world's over theirs); a path that escapes or
// meets a black surface ends early. The VPLs come path after path, each path's in bounce order. Deterministic for a
// seed, whatever the threads.
std::vector<Vpl> trace_vpls(const CpuScene& scene, std::span<const BounceLight> lights, const VplOptions& options);

// The light of each of `paths` paths, stratified: path i takes the light where (i + 0.5) / paths falls in the
// cumulative weights. Empty where no weight is positive.
std::vector<uint32_t> light_of_paths(std::span<const double> weights, int paths);

// How a render's paths are shared out among its lights. By power, a sky seen through a window spends most of its
// paths on the roof and the ground outside, and the room's share of its light rides on the few that come in: under
// a sunlit room's sky, 40-100 of 400-700 sky paths lit the camera's view samples against 750-970 of 1,300 sun
// paths, and the sky's light was the larger. So each class of lights (every lamp alone, the world's directions
// together, the emitters together) gets paths in proportion to the root of the second moment of what one of its
// paths estimates of the class's light at the view samples (its importance times the class's path count), learned
// over the render's samples: Neyman's allocation, which minimises the variance of a sum of independent estimates,
// with the second moment bounding the variance from above so that it never reaches zero. A share by power keeps
// paths for a class that has shown nothing yet. Unbiased whatever it learned: a path carries its light's power over
// its light's path count.
class PathShares {
 public:
  static constexpr double kPowerShare = 0.25;
  static constexpr double kMemory = 0.5;  // the weight of what earlier samples taught, each sample

  // A render's first sample: by power.
  void reset(std::size_t lamps);
  // The path weights (VplOptions) for a sample's lights.
  std::vector<double> weights(std::span<const BounceLight> lights, LightKinds kinds, float scene_radius) const;
  // Learns from `candidates`, traced over `paths` paths with `weights`, and their importance.
  void learn(std::span<const Vpl> candidates, std::span<const float> importance, std::span<const double> weights,
             int paths, LightKinds kinds);

 private:
  static std::size_t class_of(std::size_t light, LightKinds kinds);

  std::vector<double> second_moment_;  // per class: each lamp, the world, the emitters
};

// Calls visit(the path's first VPL, its importance: its VPLs' together) for each path of `candidates`, in
// trace_vpls' order (a path's VPLs follow one another, the first at bounce 1), with `importance` per candidate.
template <class Visit>
void for_each_path(std::span<const Vpl> candidates, std::span<const float> importance, Visit visit) {
  for (std::size_t i = 0; i < candidates.size() && i < importance.size();) {
    double path = 0.0;
    std::size_t j = i;
    do path += std::isfinite(importance[j]) && importance[j] > 0.0f ? double(importance[j]) : 0.0;
    while (++j < candidates.size() && j < importance.size() && candidates[j].bounce > 1);
    visit(candidates[i], path);
    i = j;
  }
}

// Resampled importance sampling (Talbot et al. 2005): `count` draws among candidates with probabilities p_i
// proportional to `importance` mixed with a uniform share (defensive, so no candidate has p_i = 0). A draw is
// (candidate index, 1 / (count p_i)): scaling each drawn VPL's power by it makes the image of the drawn VPLs an
// unbiased estimate of the candidates' image, whatever the importance, while most draws go where the importance
// says light matters. Systematic: one random offset `u` in [0, 1) for all draws.
struct Draw {
  std::size_t index;
  float weight;
};
std::vector<Draw> resample(std::span<const float> importance, int count, float uniform_share, float u);

// How the methods that draw VPLs by importance (Topology, SSVP) resample them.
constexpr int kCandidatesPerVpl = 8;   // candidate VPLs per VPL kept
constexpr float kUniformShare = 0.1f;  // of the resampling, so no candidate is left out (defensive mixture)
constexpr int kProbesPerAxis = 8;      // view samples the importance is measured at: a grid of 8 x 8

// The radiant power a light emits (W per channel), as the renderer lights with it: a sun's through the disk
// of radius `scene_radius` facing it.
glm::vec3 light_power(const BounceLight& light, float scene_radius);

// Irradiance (W/m^2 per channel) the VPL gives a point at x with unit normal n, unshadowed; distances below
// `clamp` count as `clamp`.
glm::vec3 vpl_irradiance(const Vpl& vpl, glm::vec3 x, glm::vec3 n, float clamp);

}  // namespace bounce::cpu
