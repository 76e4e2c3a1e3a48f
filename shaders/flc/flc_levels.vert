// Debug view (paper Fig. 3): every VPL of the sample as a dot coloured by its level, hidden by the surfaces in
// front of it.
#include "flc/flc_common.glsl"

layout(location = 0) uniform mat4 u_view_projection;

flat out vec3 v_colour;

const vec3 LEVEL_COLOURS[8] = vec3[](vec3(0.9, 0.1, 0.1), vec3(1.0, 0.55, 0.0), vec3(0.95, 0.9, 0.1),
                                    vec3(0.2, 0.8, 0.2), vec3(0.1, 0.8, 0.9), vec3(0.15, 0.3, 1.0),
                                    vec3(0.6, 0.2, 0.9), vec3(1.0, 1.0, 1.0));

void main() {
  Vpl vpl = vpls[gl_VertexID];
  int level = int(vpl.normal_level.w);
  v_colour = LEVEL_COLOURS[min(level, 7)];
  // Lifted off its surface (both sides) so the depth test against that surface keeps it.
  vec3 lift = vpl.normal_level.xyz * (1e-3 * flc.scene_radius);
  vec4 front = u_view_projection * vec4(vpl.position_scale.xyz + lift, 1.0);
  vec4 back = u_view_projection * vec4(vpl.position_scale.xyz - lift, 1.0);
  gl_Position = front.z / front.w < back.z / back.w ? front : back;
  gl_PointSize = 3.0;
}
