// The visibility cluster of every pixel's surface, on the side the camera sees it from (topology_cluster_seen),
// once per sample: the passes that test visibility read it instead of searching the grid per light.
#include "topology_visibility/visibility.glsl"

layout(binding = 1) uniform sampler2D g_albedo;
layout(binding = 2) uniform sampler2D g_normal;
layout(binding = 3) uniform sampler2D g_position;

layout(location = 0) uniform vec4 eye;  // xyz the camera's position, or with w = 1 its forward axis (orthographic)

layout(location = 0) out uint out_cluster;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  out_cluster = TOPOLOGY_NO_CLUSTER;
  if (texelFetch(g_albedo, pixel, 0).a == 0.0) return;
  vec3 x = texelFetch(g_position, pixel, 0).xyz;
  vec3 to_eye = eye.w != 0.0 ? -eye.xyz : normalize(eye.xyz - x);
  out_cluster = topology_cluster_seen(x, texelFetch(g_normal, pixel, 0).xyz, to_eye);
}
