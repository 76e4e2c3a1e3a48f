// Divergent pipeline, vertex stage: corners of the divergent triangles, read back from the buffer the regular
// pass filled (drawn with glDrawArraysIndirect, no CPU round trip; Sec. 6).
#include "flc/flc_common.glsl"

out vec3 v_position;
flat out uint v_triangle;

void main() {
  v_triangle = uint(gl_VertexID) / 3u;
  DivergentTriangle t = divergents[v_triangle];
  int corner = gl_VertexID % 3;
  v_position = corner == 0 ? t.p0_random.xyz : (corner == 1 ? t.p1_random.xyz : t.p2_random.xyz);
}
