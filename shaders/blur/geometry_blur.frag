// Geometry-aware blur, one axis per pass: a Gaussian over blur_radius pixels whose taps count only where the
// neighbour lies on the receiver's surface (its tangent plane and normal agree). It recombines the interleaved
// sub-images, whose pixels saw different VPLs, without bleeding light across edges.
layout(binding = 2) uniform sampler2D g_normal;
layout(binding = 3) uniform sampler2D g_position;
layout(binding = 12) uniform sampler2D u_source;

layout(location = 0) uniform ivec2 u_axis;
layout(location = 1) uniform int u_radius;

layout(location = 0) out vec4 out_indirect;

const float NORMAL_POWER = 16.0;
const float PLANE_TOLERANCE = 0.01;  // plane distance per unit of view depth that still counts as the surface

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(u_source, 0);
  vec4 centre = texelFetch(g_position, pixel, 0);
  vec3 n = texelFetch(g_normal, pixel, 0).xyz;
  if (dot(n, n) == 0.0) {
    out_indirect = texelFetch(u_source, pixel, 0);
    return;
  }
  float sigma = max(0.5 * float(u_radius), 0.5);
  float plane_scale = 1.0 / (PLANE_TOLERANCE * max(abs(centre.w), 1e-6));
  vec3 sum = vec3(0.0);
  float weight_sum = 0.0;
  for (int i = -u_radius; i <= u_radius; ++i) {
    ivec2 q = pixel + i * u_axis;
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
    vec3 nq = texelFetch(g_normal, q, 0).xyz;
    if (dot(nq, nq) == 0.0) continue;
    float plane = dot(n, texelFetch(g_position, q, 0).xyz - centre.xyz) * plane_scale;
    float w = exp(-0.5 * float(i * i) / (sigma * sigma)) * pow(max(dot(n, nq), 0.0), NORMAL_POWER) *
              exp(-plane * plane);
    sum += w * texelFetch(u_source, q, 0).rgb;
    weight_sum += w;
  }
  out_indirect = vec4(weight_sum > 0.0 ? sum / weight_sum : vec3(0.0), 0.0);
}
