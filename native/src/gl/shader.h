// GLSL programs built from the shader sources embedded at build time (shaders/ → shader_sources.cpp).
// Every stage gets `#version 450 core`, the settings uniform block, and `#include "dir/file.glsl"` resolved
// against shaders/.
#pragma once

#include <string>
#include <vector>

#include "gl/objects.h"

namespace bounce::gl {

struct StageSource {
  GLenum stage;      // GL_VERTEX_SHADER, ...
  std::string path;  // relative to shaders/, e.g. "gbuffer/gbuffer.vert"; names the stage in errors
  std::string text;  // when set, the source itself instead of the embedded file at `path` (tests)
};

// Compiles and links; throws Error(BOUNCE_ERROR_GL) with the compiler log, naming the file.
Program build_program(const std::vector<StageSource>& stages, const std::string& defines = "");

// The text of an embedded file with its #includes expanded (for tests and the shader build).
std::string shader_text(const std::string& path);

}  // namespace bounce::gl
