// View samples for the methods that draw their VPLs by importance (SSVP's VPL Importance, Forward Light Cuts' light
// candidates): where the light a VPL gives reaches what the camera sees.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "cpu/cpu_scene.h"
#include "cpu/vpls.h"

namespace bounce::cpu {

struct ViewProbe {
  glm::vec3 position, normal, albedo;  // normal: the shading normal, toward the camera
};

// The surface a camera ray meets through one jittered point in each cell of a per_axis^2 grid over the whole view of
// `view_projection` (all the tiles of a tiled frame share them), as the rasterizer sees it (cut-outs let the ray
// through). Deterministic for a seed.
std::vector<ViewProbe> camera_probes(const glm::mat4& view_projection, const CpuScene& scene, uint32_t seed,
                                     int per_axis = kProbesPerAxis);

}  // namespace bounce::cpu
