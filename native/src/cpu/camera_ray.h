// Primary rays of Blender's camera matrices (perspective or orthographic), for the CPU code.
#pragma once

#include <cmath>
#include <limits>
#include <optional>

#include <glm/glm.hpp>

namespace bounce::cpu {

struct CameraRay {
  glm::vec3 origin{0.0f}, direction{0.0f};  // direction unit; both non-finite for a degenerate camera
  float tmax = 0.0f;                        // the far plane; infinite for an infinite one
};

// The ray through normalized device coordinates (x, y) in [-1, 1]^2 of clip_to_world = inverse(projection *
// world_to_view), from the near plane to the far one.
inline CameraRay camera_ray(const glm::dmat4& clip_to_world, double ndc_x, double ndc_y) {
  const glm::dvec4 near = clip_to_world * glm::dvec4(ndc_x, ndc_y, -1.0, 1.0);
  const glm::dvec4 far = clip_to_world * glm::dvec4(ndc_x, ndc_y, 1.0, 1.0);
  const glm::dvec3 origin = glm::dvec3(near) / near.w;
  const bool finite_far = std::abs(far.w) > 1e-12 * std::abs(near.w);
  const glm::dvec3 span = finite_far ? glm::dvec3(far) / far.w - origin : glm::dvec3(far);
  const double tmax = finite_far ? glm::length(span) : std::numeric_limits<double>::infinity();
  return {glm::vec3(origin), glm::vec3(glm::normalize(span)), static_cast<float>(tmax)};
}

// camera_ray's inverse: where p falls in an image of width x height pixels (continuous, pixel (0, 0) covering
// [0, 1)^2) through world_to_clip = projection * world_to_view; none where p is behind the camera.
inline std::optional<glm::dvec2> image_point(const glm::dmat4& world_to_clip, glm::dvec3 p, int width, int height) {
  const glm::dvec4 clip = world_to_clip * glm::dvec4(p, 1.0);
  if (!(clip.w > 0.0)) return std::nullopt;
  return (glm::dvec2(clip) / clip.w * 0.5 + 0.5) * glm::dvec2(width, height);
}

}  // namespace bounce::cpu
