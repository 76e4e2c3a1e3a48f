// Lambert's polygon formula of shaders/common/lambert_shared.glsl, compiled for the host: the CPU's direct light
// computes area lights' unshadowed irradiance exactly as the shaders do.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

namespace bounce::cpu::lambert {

using glm::abs;
using glm::atan;
using glm::cos;
using glm::cross;
using glm::dot;
using glm::length;
using glm::mix;
using glm::normalize;
using glm::sin;
using glm::sqrt;
using glm::vec3;

#define LAMBERT_INLINE inline
#define LAMBERT_OUT
#include "common/lambert_shared.glsl"
#undef LAMBERT_OUT
#undef LAMBERT_INLINE

}  // namespace bounce::cpu::lambert
