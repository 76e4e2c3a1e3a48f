// Divergent pipeline, tessellation evaluation: each generated vertex fetches its random from a noise texture
// at its barycentric coordinates (Alg. 2, DivergentRand; Fig. 8).
#include "flc/flc_common.glsl"

layout(triangles, equal_spacing, ccw) in;

in vec3 c_position[];
flat in uint c_triangle[];
out vec3 e_position;
flat out uint e_triangle;
flat out uint e_noise_random;

layout(binding = 11) uniform usampler2D u_noise;

void main() {
  vec3 b = gl_TessCoord;
  e_position = b.x * c_position[0] + b.y * c_position[1] + b.z * c_position[2];
  e_triangle = c_triangle[0];
  ivec2 size = textureSize(u_noise, 0);
  e_noise_random = texelFetch(u_noise, ivec2(b.xy * vec2(size - 1) + 0.5), 0).r;
}
