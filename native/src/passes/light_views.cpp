#include "passes/light_views.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "radiometry.h"

namespace bounce {

namespace {
constexpr float kWidestPerspectiveHalfAngle = 75.0f * kPi / 180.0f;
}  // namespace

int size_within_budget(int size, int min_size, double layers, double bytes_per_texel, double budget) {
  while (size > min_size && layers * bytes_per_texel * double(size) * double(size) > budget) size /= 2;
  return size;
}

glm::vec3 vec3_of(const float* v) { return {v[0], v[1], v[2]}; }

glm::vec3 any_perpendicular(glm::vec3 unit) {
  const glm::vec3 axis = std::abs(unit.z) < 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0);
  return glm::normalize(glm::cross(unit, axis));
}

LightViewKind light_view_kind(const BounceLight& light) {
  if (light.type == BOUNCE_LIGHT_SUN) return kLightViewOrthographic;
  if (light.type == BOUNCE_LIGHT_SPOT && light.spot_half_angle <= kWidestPerspectiveHalfAngle)
    return kLightViewPerspective;
  return kLightViewCube;
}

LightViews light_views(const BounceLight& light, glm::vec3 origin, glm::vec3 lo, glm::vec3 hi, int size) {
  LightViews v;
  v.kind = light_view_kind(light);
  v.eye = origin;
  const glm::vec3 centre = 0.5f * (lo + hi);
  if (v.kind == kLightViewOrthographic) {
    const float radius = std::max(0.5f * glm::length(hi - lo), 1e-6f) * 1.01f;
    v.faces = 1;
    v.view[0] = glm::lookAt(centre + origin * (2.0f * radius), centre, any_perpendicular(origin));
    v.near_plane = 0.5f * radius;
    v.far_plane = 3.5f * radius;
    v.view_projection[0] = glm::ortho(-radius, radius, -radius, radius, v.near_plane, v.far_plane) * v.view[0];
    v.texel_factor = 2.0f * radius / static_cast<float>(size);
    return v;
  }
  float farthest = 0.0f;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z);
    farthest = std::max(farthest, glm::length(p - origin));
  }
  v.far_plane = std::max(farthest * 1.05f, 1e-5f);
  v.near_plane = v.far_plane * 1e-4f;
  if (v.kind == kLightViewPerspective) {
    const float half_fov = std::min(light.spot_half_angle + 0.035f, 1.5f);
    v.faces = 1;
    v.view[0] = glm::lookAt(origin, origin - vec3_of(light.axis_z), vec3_of(light.axis_y));
    v.view_projection[0] = glm::perspective(2.0f * half_fov, 1.0f, v.near_plane, v.far_plane) * v.view[0];
    v.texel_factor = 2.0f * std::tan(half_fov) / static_cast<float>(size);
    return v;
  }
  static const glm::vec3 directions[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  static const glm::vec3 ups[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
  const glm::mat3 frame(vec3_of(light.axis_x), vec3_of(light.axis_y), vec3_of(light.axis_z));
  const glm::mat4 projection = glm::perspective(0.5f * kPi, 1.0f, v.near_plane, v.far_plane);
  v.faces = 6;
  for (int f = 0; f < 6; ++f) {
    v.view[f] = glm::lookAt(origin, origin + frame * directions[f], frame * ups[f]);
    v.view_projection[f] = projection * v.view[f];
  }
  v.skipped_face = light.type == BOUNCE_LIGHT_POINT || light.type == BOUNCE_LIGHT_AREA_TRIANGLE ? -1 : 4;
  v.texel_factor = 2.0f / static_cast<float>(size);
  return v;
}

}  // namespace bounce
