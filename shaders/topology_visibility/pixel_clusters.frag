// The visibility cluster of every pixel's surface, on the side facing the camera (the G-buffer's normal), once per
// sample: the passes that test visibility read it instead of searching the grid per light.
#include "topology_visibility/visibility.glsl"

layout(binding = 1) uniform sampler2D g_albedo;
layout(binding = 2) uniform sampler2D g_normal;
layout(binding = 3) uniform sampler2D g_position;

layout(location = 0) out uint out_cluster;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  out_cluster = TOPOLOGY_NO_CLUSTER;
  if (texelFetch(g_albedo, pixel, 0).a == 0.0) return;
  out_cluster = topology_cluster_at(texelFetch(g_position, pixel, 0).xyz, texelFetch(g_normal, pixel, 0).xyz);
}
