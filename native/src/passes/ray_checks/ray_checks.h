#pragma once
// Ray Checks: a control variate on a GL pass's visibility rule (the topology's clusters and gates for Forward Light
// Cuts, the clustered paraboloid maps for SSVP), as the Topology method's Ray Checks (cpu::TopologyRenderer). The
// pass's shader appends a random share of its light-pixel pairs, lit or not by the rule, with the rule's verdict
// and the pair's unshadowed light (shaders/ray_checks/ray_checks.glsl); an Embree shadow ray checks each, and
// (ray - rule) x unshadowed / share is added to the pixel, so the image's expectation is the shadow rays' whatever
// the rule gets wrong, at the cost of the checks' rays and of their noise where the rule is often wrong.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "cpu/cpu_scene.h"
#include "gl/objects.h"

namespace bounce {

// What a pass is asked to check: the scene its shadow rays meet, and the share of its pairs, in (0, 1].
struct RayCheckSettings {
  const cpu::CpuScene& scene;
  float share;
};

class RayChecks {
 public:
  struct Pair {               // std430 mirror of shaders/ray_checks/ray_checks.glsl `RayCheck`
    glm::vec4 light_verdict;  // the light's position, the rule's verdict
    glm::vec4 light_normal;   // w 1: the pair corrects correct()'s `also` too
    glm::vec4 receiver;       // the pixel's surface point
    glm::vec4 receiver_normal;
    glm::vec3 unshadowed;  // the light's share of the pixel, unshadowed
    uint32_t pixel;        // y * width + x
  };

  // Before the pass's shader runs: room for about one pair a pixel (or as many as a sample asked for before),
  // the count cleared, the buffer bound where the shader's include expects it.
  void bind(std::size_t pixels);
  // After it: the pairs read back and checked by shadow rays; each correction added to `image` (RGBA32F,
  // `width` x `height`), and to `also` (0: none) for the pairs the shader marked.
  void correct(const RayCheckSettings& checks, GLuint image, GLuint also, int width, int height);

 private:
  void add_to(GLuint image, int width, int height, float weight, bool marked_only);

  gl::Buffer buffer_;  // the count (and padding to 16 bytes), then the pairs
  std::size_t bytes_ = 0;
  std::size_t wanted_ = 0;  // pairs: the most a sample asked for
  std::vector<Pair> pairs_;
  std::vector<float> seen_;  // per pair, 1 where its shadow ray is clear
  std::vector<glm::vec4> light_;
};

}  // namespace bounce
