// The scene file benchmarks/cpu_reference_export.py writes inside Blender: what the add-on's export hands the C API
// (camera, lights, triangles), with one albedo per triangle. bounce_reference_render renders it with the CPU model,
// bounce_scene_bench with the engine itself, so both run on machines without Blender. Little-endian binary:
//
//   char[8]  "BNCREF1\n"
//   int32    sizeof(BounceCamera), sizeof(BounceLight)   (checked: the writer used this bounce.h)
//   int32    light_samples (the CPU model's Options)
//   float32  epsilon_fraction (of the scene radius, as flc_epsilon), points (the target count of surface points)
//   BounceCamera
//   int32    light count, then that many BounceLight
//   int64    triangle count, then per triangle 12 float32: three world-space corners, then the albedo
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bounce/bounce.h"
#include "reference/flc_reference.h"

namespace bounce::reference {

struct SceneFile {
  int32_t light_samples = 0;
  float epsilon_fraction = 0.0f;
  float points = 0.0f;
  BounceCamera camera{};
  std::vector<BounceLight> lights;
  std::vector<Triangle> triangles;
};

// Throws std::runtime_error naming what is wrong with the file.
SceneFile read_scene_file(const std::string& path);

}  // namespace bounce::reference
