// Divergent pipeline, tessellation control: subdivide until every sub-triangle is regular (area below
// S-bar_N). A uniform level t splits a triangle into about t^2 parts; the margin covers their unequal areas.
// The pattern depends only on the triangle's area, so its randoms are stable while it keeps its shape (Sec. 6).
#include "flc/flc_common.glsl"

layout(vertices = 3) out;

in vec3 v_position[];
flat in uint v_triangle[];
out vec3 c_position[];
flat out uint c_triangle[];

const float SUBDIVISION_MARGIN = 1.5;

void main() {
  c_position[gl_InvocationID] = v_position[gl_InvocationID];
  c_triangle[gl_InvocationID] = v_triangle[gl_InvocationID];
  if (gl_InvocationID == 0) {
    float area = 0.5 * length(cross(v_position[1] - v_position[0], v_position[2] - v_position[0]));
    float level = clamp(ceil(SUBDIVISION_MARGIN * sqrt(area * flc.inverse_cumulative_n)), 1.0, flc.max_tess_level);
    gl_TessLevelOuter[0] = level;
    gl_TessLevelOuter[1] = level;
    gl_TessLevelOuter[2] = level;
    gl_TessLevelInner[0] = level;
  }
}
