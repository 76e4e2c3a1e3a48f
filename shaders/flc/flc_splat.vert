// Splatting, vertex stage: one point per VPL (drawn with glDrawArraysIndirect from the generation count).
#include "flc/flc_common.glsl"

flat out uint v_vpl;

void main() {
  v_vpl = uint(gl_VertexID);
  gl_Position = vec4(0.0);
}
