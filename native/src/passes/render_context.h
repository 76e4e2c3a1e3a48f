// What every pass of one sample sees: the scene, the settings, the camera of the tile, the sample index.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "bounce/bounce.h"
#include "gpu_scene.h"
#include "stage_timer.h"

namespace bounce {

struct RenderContext {
  const GpuScene& scene;
  const std::vector<BounceLight>& lights;  // this sample's (SceneLights): lamps, world directions, emitters
  const BounceSettings& settings;
  StageTimer& timer;
  int width, height;          // of the tile being rendered
  glm::ivec2 tile_origin;     // the tile's lower-left pixel in the image
  glm::mat4 view_projection;  // jittered, cropped to the tile
  glm::mat4 world_to_view;
  glm::vec3 camera_position;
  glm::vec3 camera_forward;
  bool orthographic;
  uint32_t sample;  // progressive sample index
  uint32_t seed;    // settings.seed mixed with the frame number
};

// A vertex array with no attributes, for draws whose shaders fetch their own data (render thread only).
GLuint empty_vertex_array();

// Draws the fullscreen triangle of shaders/common/fullscreen.vert.
void draw_fullscreen_triangle();

}  // namespace bounce
