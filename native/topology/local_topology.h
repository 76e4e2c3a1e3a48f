// Topology of a voxel's 3x3x3 neighbourhood, for the empty space as the object (26-adjacency) and the solid
// as the background (6-adjacency), the pair of digital topology that keeps the two separated (Kong and
// Rosenfeld 1989). Neighbours are bits 0..25 in the order of neighbour_offsets().
#pragma once

#include <array>
#include <cstdint>

namespace bounce::topology {

struct LocalTopology {
  // Number of 26-connected components of the object in the 26 neighbours (T26 of Bertrand and Malandain
  // 1994), counted up to 2.
  int object_components = 0;
  // The 6-connected components of the background in the 18 neighbours that are 6-adjacent to the centre
  // (T6-bar), as masks, at most 6.
  int background_components = 0;
  std::array<uint32_t, 6> background_masks{};

  // A simple point: removing it changes no topology (T26 = 1 and T6-bar = 1).
  bool simple() const { return object_components == 1 && background_components == 1; }
  // A curve point in the sense of the 1-D isthmus (Couprie and Bertrand 2014): the object around it falls
  // apart without it.
  bool isthmus() const { return object_components >= 2; }
};

// object: bit i set where neighbour i belongs to the object; every other neighbour is background.
LocalTopology classify_neighbourhood(uint32_t object);

// Mask of the 6 face neighbours.
uint32_t face_neighbours();

}  // namespace bounce::topology
