// Constants and conversions of light shared by the host-side passes, the analysis and the CPU renderers.
#pragma once

#include <glm/glm.hpp>

namespace bounce {

inline constexpr float kPi = 3.14159265358979f;

// Luminance of linear Rec. 709 RGB, Blender's scene-linear space: how bright a colour, a light's power or a
// component of the image is, as one number.
inline float luminance(glm::vec3 rgb) { return 0.2126f * rgb.r + 0.7152f * rgb.g + 0.0722f * rgb.b; }

}  // namespace bounce
