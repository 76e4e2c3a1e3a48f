// The Forward Light Cuts functions of shaders/flc/flc_shared.glsl, compiled for the host: the pass sizes its
// buffers and draws with them, and the unit tests check them against the paper's definitions.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "sampling.h"

namespace bounce::flc {

using glm::max;
using glm::sqrt;
using glm::vec3;
using uint = uint32_t;

#define FLC_INLINE inline
#include "flc/flc_shared.glsl"
#undef FLC_INLINE

}  // namespace bounce::flc
