// Divergent pipeline, vertex stage: corners of the divergent triangles, read back from the buffer the regular
// pass filled (drawn with glDrawArraysIndirect, no CPU round trip; Sec. 6). One instance per triangle: Mesa's
// llvmpipe (22.3) numbers the tessellated vertices of a draw instance with 16 bits, so past 65,536 of them (about
// 20 triangles at level 64) its geometry shader receives triangles of wrong corners, far larger than the
// triangle's parts; FLC's light grew with N_avg as the levels rose. Instances are tessellated one by one.
#include "flc/flc_common.glsl"

out vec3 v_position;
flat out uint v_triangle;

void main() {
  v_triangle = uint(gl_InstanceID);
  DivergentTriangle t = divergents[v_triangle];
  int corner = gl_VertexID;
  v_position = corner == 0 ? t.p0_random.xyz : (corner == 1 ? t.p1_random.xyz : t.p2_random.xyz);
}
