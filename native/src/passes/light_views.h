// The views a light is seen from: the shadow maps and SSVP's reflective shadow map share them.
// Sun: orthographic, fitted to the scene's bounding sphere. Spot up to 75 degrees: one perspective face over
// its cone. Point, area and wider spots: the six faces of a cube around the light, in the GL cube-map order and
// orientation (+X, -X, +Y, -Y, +Z, -Z) of the light's own frame; a light that emits along -z only (area, spot)
// never lights its +z face, which is then skipped (a triangle light emits from both sides).
#pragma once

#include <array>

#include <glm/glm.hpp>

#include "bounce/bounce.h"

namespace bounce {

enum LightViewKind { kLightViewNone = 0, kLightViewOrthographic = 1, kLightViewPerspective = 2, kLightViewCube = 3 };

struct LightViews {
  LightViewKind kind = kLightViewNone;
  int faces = 0;          // 1, or 6 for a cube
  int skipped_face = -1;  // a cube face nothing is emitted into, or -1
  std::array<glm::mat4, 6> view{}, view_projection{};
  glm::vec3 eye{0.0f};  // perspective: the view's origin; orthographic: the unit direction towards the light
  float near_plane = 0.0f, far_plane = 0.0f;
  float texel_factor = 0.0f;  // orthographic: a texel's side in world units; perspective: 2 tan(half fov) / size
};

LightViewKind light_view_kind(const BounceLight& light);

// The views of `light` seen from `origin` (a point of the light; for a sun the unit direction towards it) over
// the scene's bounds [lo, hi], for maps of `size` texels a side.
LightViews light_views(const BounceLight& light, glm::vec3 origin, glm::vec3 lo, glm::vec3 hi, int size);

// The first of size, size / 2, size / 4, ... at which `layers` square layers of `bytes_per_texel` fit in
// `budget` bytes, or the first at or below min_size: how the maps seen from lights (shadow maps, SSVP's reflective
// shadow map and paraboloid maps) stay within GPU memory at any setting.
int size_within_budget(int size, int min_size, double layers, double bytes_per_texel, double budget);

glm::vec3 vec3_of(const float* v);
glm::vec3 any_perpendicular(glm::vec3 unit);

}  // namespace bounce
