#include "local_topology.h"

#include <algorithm>
#include <bit>
#include <cstdlib>

#include "voxel_grid.h"

namespace bounce::topology {

namespace {

struct Masks {
  std::array<uint32_t, 26> adjacent26{};  // neighbours of i (within the 26) that are 26-adjacent to it
  std::array<uint32_t, 26> adjacent6{};   // neighbours of i within the 18 that are 6-adjacent to it
  uint32_t within18 = 0;                  // the 18 face and edge neighbours
  uint32_t faces = 0;                     // the 6 face neighbours
};

const Masks& masks() {
  static const Masks m = [] {
    Masks r;
    const auto& o = neighbour_offsets();
    for (int i = 0; i < 26; ++i) {
      const int li = std::abs(o[i].x) + std::abs(o[i].y) + std::abs(o[i].z);
      if (li <= 2) r.within18 |= 1u << i;
      if (li == 1) r.faces |= 1u << i;
    }
    for (int i = 0; i < 26; ++i) {
      for (int j = 0; j < 26; ++j) {
        if (i == j) continue;
        const glm::ivec3 d = o[i] - o[j];
        const int chebyshev = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
        const int l1 = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
        if (chebyshev <= 1) r.adjacent26[i] |= 1u << j;
        if (l1 == 1 && (r.within18 >> i & 1) && (r.within18 >> j & 1)) r.adjacent6[i] |= 1u << j;
      }
    }
    return r;
  }();
  return m;
}

// The component of `set` that holds `seed`, by flooding along `adjacent`.
uint32_t flood(uint32_t seed, uint32_t set, const std::array<uint32_t, 26>& adjacent) {
  uint32_t component = seed, frontier = seed;
  while (frontier) {
    uint32_t grown = 0;
    for (uint32_t f = frontier; f; f &= f - 1) grown |= adjacent[size_t(std::countr_zero(f))];
    grown &= set & ~component;
    component |= grown;
    frontier = grown;
  }
  return component;
}

}  // namespace

uint32_t face_neighbours() { return masks().faces; }

LocalTopology classify_neighbourhood(uint32_t object) {
  const Masks& m = masks();
  LocalTopology t;
  object &= (1u << 26) - 1;
  for (uint32_t rest = object; rest && t.object_components < 2; ++t.object_components) {
    rest &= ~flood(rest & (~rest + 1), rest, m.adjacent26);
  }
  uint32_t background = ~object & m.within18;
  for (uint32_t seeds = background & m.faces; seeds;) {
    const uint32_t component = flood(seeds & (~seeds + 1), background, m.adjacent6);
    t.background_masks[size_t(t.background_components++)] = component;
    seeds &= ~component;
    background &= ~component;
  }
  return t;
}

}  // namespace bounce::topology
