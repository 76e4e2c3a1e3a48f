// Virtual point lights traced from every light with Embree (Instant Radiosity, Keller 1997; Noel and Biri 2014,
// Sec. V and Fig. 8): paths leave the lights in proportion to their power, and each diffuse hit leaves a VPL
// carrying the path's power reflected there.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "bounce/bounce.h"
#include "cpu/cpu_scene.h"

namespace bounce::cpu {

struct Vpl {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f};    // unit, on the side the light arrived from: the VPL lights that half-space
  glm::vec3 power{0.0f};     // W per channel leaving the VPL (albedo included), spread as cos / pi
  uint32_t bounce = 1;       // 1: lit straight by a lamp
  uint32_t light = 0;        // the index of the light its path left
  glm::vec2 emission{0.0f};  // the point of the light's emission square its path left from (EmissionGuide)
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

struct VplOptions {
  int paths = 1024;  // paths traced from the lights, all of them
  int bounces = 1;   // diffuse hits per path, each leaving a VPL
  uint64_t seed = 0;
  std::span<const EmissionGuide> guides;  // per light, by index; the lights past its end emit uniformly
};

// Paths are shared out among the lights in proportion to their power; a path that escapes or meets a black
// surface ends early. Deterministic for a seed, whatever the threads.
std::vector<Vpl> trace_vpls(const CpuScene& scene, std::span<const BounceLight> lights, const VplOptions& options);

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
