// The light the distance clamp takes, given back from the screen (Kollig and Keller 2006, bias compensation).
// A VPL closer than the clamp c to a receiver counts as c away, so Forward Light Cuts (Eq. 5) and SSVP leave out,
// of the first bounce's irradiance at x, the integral over the surfaces y within c of
//     L_direct(y) (1 - d^2 / c^2) cos(theta_x) dw.
// Each pixel draws RAYS cosine-distributed directions, marches each one through the G-buffer up to c, and where
// it passes behind a visible surface y that faces it at a distance d < c, adds L_direct(y) (1 - d^2 / c^2): with
// the pdf cos / pi, the estimate of that integral over pi. The Direct target holds L_direct (albedo / pi * E).
// Surfaces hidden from the camera or outside the tile give nothing back, as the clamp did; with Ray Traced shadows
// Embree traces the same ray instead (cpu/near_field.h).
#include "common/random.glsl"

layout(binding = 1) uniform sampler2D g_albedo;
layout(binding = 2) uniform sampler2D g_normal;
layout(binding = 3) uniform sampler2D g_position;
layout(binding = 5) uniform sampler2D g_geometric_normal;
layout(binding = 8) uniform sampler2D direct_light;

layout(location = 0) uniform mat4 u_view_projection;  // of this tile, jittered
layout(location = 1) uniform mat4 u_world_to_view;    // its -z is the G-buffer's view depth
layout(location = 2) uniform float u_clamp;           // c, metres
layout(location = 3) uniform ivec2 u_tile_origin;     // so the rays do not depend on the tiling
layout(location = 4) uniform uint u_sample_seed;

layout(location = 0) out vec4 out_near_field;  // irradiance / pi

const int RAYS = 4;
const int STEPS = 8;
const int BISECTIONS = 3;
const float PI = 3.14159265358979;

vec3 cosine_direction(vec3 n, vec2 u) {
  float r = sqrt(u.x), phi = 2.0 * PI * u.y;
  vec3 t = normalize(abs(n.z) < 0.999 ? cross(n, vec3(0.0, 0.0, 1.0)) : cross(n, vec3(1.0, 0.0, 0.0)));
  vec3 b = cross(n, t);
  return normalize(r * cos(phi) * t + r * sin(phi) * b + sqrt(max(1.0 - u.x, 0.0)) * n);
}

// Where the ray at distance t lies behind the visible surface of its pixel by no more than c: that pixel, else
// (-1, -1). Off the tile or behind the camera: (-2, -2).
ivec2 behind_surface(vec3 x, vec3 w, float t, ivec2 size) {
  vec3 p = x + t * w;
  vec4 clip = u_view_projection * vec4(p, 1.0);
  if (clip.w <= 0.0) return ivec2(-2);
  ivec2 q = ivec2(floor((clip.xy / clip.w * 0.5 + 0.5) * vec2(size)));
  if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) return ivec2(-2);
  if (texelFetch(g_albedo, q, 0).a == 0.0) return ivec2(-1);
  float behind = -(u_world_to_view * vec4(p, 1.0)).z - texelFetch(g_position, q, 0).w;
  return behind > 0.0 && behind <= u_clamp ? q : ivec2(-1);
}

// L_direct(y) (1 - t^2 / c^2) for the first visible surface y facing the ray that it meets at a distance t < c;
// 0 where none. t comes from bisecting the step that crossed the surface, not from the distance to the pixel's
// own point, whose footprint can be as wide as c.
vec3 march(vec3 x, vec3 w, float jitter, ivec2 size) {
  float step = u_clamp / float(STEPS);
  float before = 0.0;
  for (int i = 0; i < STEPS; ++i) {
    float t = step * (float(i) + jitter);
    ivec2 q = behind_surface(x, w, t, size);
    if (q.x == -2) return vec3(0.0);
    // Not behind a surface, or behind one that faces away: the ray goes on (grazing views show the receiver's own
    // plane behind points just above it).
    if (q.x < 0 || dot(texelFetch(g_normal, q, 0).xyz, w) >= 0.0) {
      before = t;
      continue;
    }
    for (int k = 0; k < BISECTIONS; ++k) {
      float middle = 0.5 * (before + t);
      if (behind_surface(x, w, middle, size).x >= 0)
        t = middle;
      else
        before = middle;
    }
    t = 0.5 * (before + t);
    return texelFetch(direct_light, q, 0).rgb * max(1.0 - t * t / (u_clamp * u_clamp), 0.0);
  }
  return vec3(0.0);
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  out_near_field = vec4(0.0);
  if (texelFetch(g_albedo, pixel, 0).a == 0.0 || !(u_clamp > 0.0)) return;
  vec3 x = texelFetch(g_position, pixel, 0).xyz;
  vec3 n = texelFetch(g_normal, pixel, 0).xyz;
  vec3 ng = texelFetch(g_geometric_normal, pixel, 0).xyz;
  ivec2 size = textureSize(g_position, 0);
  ivec2 image_pixel = pixel + u_tile_origin;
  uint key = pcg_hash(u_sample_seed ^ pcg_hash(uint(image_pixel.x) ^ pcg_hash(uint(image_pixel.y))));
  // RAYS strata of the unit square, shifted together per pixel (Cranley-Patterson).
  vec2 shift = vec2(hash_to_unit(key), hash_to_unit(key + 1u));
  vec3 sum = vec3(0.0);
  for (int r = 0; r < RAYS; ++r) {
    vec2 u = fract(vec2((float(r & 1) + 0.5) * 0.5, (float(r >> 1) + 0.5) * 0.5) + shift);
    vec3 w = cosine_direction(n, u);
    if (dot(w, ng) <= 0.0) continue;  // below the surface: the shading normal bends past the geometric one
    sum += march(x, w, hash_to_unit(key + 2u + uint(r)), size);
  }
  out_near_field = vec4(sum / float(RAYS), 0.0);
}
