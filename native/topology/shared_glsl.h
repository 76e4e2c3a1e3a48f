// The visibility functions the shaders share with the CPU (shaders/topology_visibility/*_shared.glsl, written in
// the common subset of GLSL and C++), compiled into C++ with GLM: the gate test, the octahedral map and its
// direction bins. For the topology's estimates, the Topology method and the GPU pass's upload.
#pragma once

#include <algorithm>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace bounce::topology::shared {
using glm::abs;
using glm::cross;
using glm::dot;
using glm::length;
using glm::normalize;
using glm::vec2;
using glm::vec3;
using std::min;
#define GATES_INLINE inline
#include "topology_visibility/gates_shared.glsl"
#undef GATES_INLINE
#define PASSAGES_INLINE inline
#include "topology_visibility/passages_shared.glsl"
#undef PASSAGES_INLINE
}  // namespace bounce::topology::shared
