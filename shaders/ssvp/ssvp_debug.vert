// Debug view: the sample's VPLs as dots in their cluster's colour (first bounce bright, second bounce small and
// darker, in the colour of the cluster whose map shadows it) and each cluster's centre as a large dot, hidden by
// the surfaces in front of them.
#include "ssvp/ssvp_common.glsl"

layout(location = 0) uniform mat4 u_view_projection;
layout(location = 1) uniform int u_kind;  // 0 first-bounce VPLs, 1 second-bounce VPLs, 2 cluster centres

flat out vec3 v_colour;

// Hues a golden angle apart, so neighbouring cluster indices get distinct colours.
vec3 cluster_colour(int c) {
  float hue = fract(float(c) * 0.618034);
  vec3 rgb = clamp(abs(fract(hue + vec3(0.0, 2.0 / 3.0, 1.0 / 3.0)) * 6.0 - 3.0) - 1.0, 0.0, 1.0);
  return mix(vec3(1.0), rgb, 0.85);
}

void main() {
  vec3 position, normal;
  int cluster;
  bool exists = true;
  if (u_kind == 2) {
    position = clusters[gl_VertexID].position_first.xyz;
    normal = clusters[gl_VertexID].normal_count.xyz;
    cluster = gl_VertexID;
    gl_PointSize = 11.0;
  } else {
    Vpl vpl = u_kind == 0 ? first_vpls[gl_VertexID] : second_vpls[gl_VertexID];
    position = vpl.position_cluster.xyz;
    normal = vpl.normal.xyz;
    cluster = int(vpl.position_cluster.w);
    exists = vpl.flux.w != 0.0;
    gl_PointSize = u_kind == 0 ? 6.0 : 3.0;
  }
  v_colour = u_kind == 1 ? 0.6 * cluster_colour(cluster) : cluster_colour(cluster);
  // Lifted off its surface (both sides) so the depth test against that surface keeps it.
  vec3 lift = normal * (1e-3 * ssvp.length_scale);
  vec4 front = u_view_projection * vec4(position + lift, 1.0);
  vec4 back = u_view_projection * vec4(position - lift, 1.0);
  gl_Position = exists ? (front.z / front.w < back.z / back.w ? front : back) : vec4(2.0, 2.0, 2.0, 1.0);
}
