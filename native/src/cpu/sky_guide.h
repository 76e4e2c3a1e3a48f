// Directions in which points of a region see the world's light, learned over a render's samples: the third
// strategy of the world's direct light (direct_light.h, WorldStrategies). Inside a room lit through its windows,
// the table's directions (the bright sky) mostly meet walls and the cosine-weighted ones mostly the ceiling, so
// each point found the sky with a few of its eight rays a sample. A grid of boxes over the scene holds, per box,
// the light its points' rays found per bin of direction (bins of equal solid angle), and a guided direction picks
// a bin by it: the sky through the windows of the room the box is in (path guiding, after Vorba et al. 2014 and
// Müller et al. 2017, with a fixed grid). Multiple importance sampling with the other two weighs it by its density,
// which keeps the estimate unbiased only if the guide does not depend on the directions it weighs: a pixel's
// directions are points of its own stratified sequences, spread over its samples, so a guide learned from its
// earlier points steers the weights of its later ones (a plane under a uniform sky seen by 16 x 16 pixels got 1.14
// of its light at 16 samples). So the guide has two sides: each sequence (Progression's key) learns into the side
// of its key's parity and reads the other, learned from other sequences, which are independent of its own.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "cpu/box_grid.h"
#include "sampling.h"

namespace bounce::cpu {

class SkyGuide {
 public:
  static constexpr int kCellsPerSide = 8;
  static constexpr int kBins = sphere_bins::kCount;

  SkyGuide() = default;
  SkyGuide(glm::vec3 lo, glm::vec3 hi);
  // Adds `share` of light, in [0, 1] of the most a direction can find, found from x toward unit w, to side `side`
  // (0 or 1). Safe from many threads at once, but not with update(); in fixed point, so the sums, and the render,
  // do not depend on the threads' order.
  void learn(uint32_t side, glm::vec3 x, glm::vec3 w, float share);
  // Rebuilds the boxes' densities from what was learned.
  void update();
  // These read the side other than `side`. Whether the guide draws directions at x: x's box has learned light.
  bool guides(uint32_t side, glm::vec3 x) const;
  // The density per steradian with which draw() at x gives unit w; 0 where it does not guide.
  float pdf(uint32_t side, glm::vec3 x, glm::vec3 w) const;
  struct Draw {
    glm::vec3 direction;
    float pdf;
  };
  // The direction that `pick` (the bin) and `within` (the point in it), uniform in [0, 1), draw at x.
  std::optional<Draw> draw(uint32_t side, glm::vec3 x, float pick, glm::vec2 within) const;

 private:
  // x's box's bins on the side other than `side`: kBins + 1 cumulative sums from 0, the last 0 where nothing was
  // learned; none outside the grid.
  const double* cdf(uint32_t side, glm::vec3 x) const;

  BoxGrid grid_;
  std::vector<uint64_t> learned_;  // per side, box and bin, in units of 2^-32
  std::vector<double> cdf_;        // per side and box, kBins + 1 cumulative sums
};

}  // namespace bounce::cpu
