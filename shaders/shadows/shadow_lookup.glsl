// Visibility of a light from a receiver, read from the shadow maps of native/src/passes/shadows: a blocker
// search and a percentage-closer filter over the penumbra of this sample's share of the light (PCSS, Fernando
// 2005). With shadow_soft.x = 0 it is a single 2x2 hardware-filtered lookup.
#include "common/lights.glsl"
#include "common/random.glsl"

layout(binding = 6) uniform sampler2DShadow shadow_map_2d;
layout(binding = 7) uniform samplerCubeShadow shadow_map_cube;
layout(binding = 9) uniform sampler2D shadow_depth_2d;     // the same maps, raw depth
layout(binding = 10) uniform samplerCube shadow_depth_cube;

const int SHADOW_TAPS = 12;
const float MAX_FILTER_TEXELS = 16.0;

int shadow_kind() { return int(light.shadow_params.x); }

// Depth-buffer value -> distance from the light along the map's axis.
float shadow_linear_depth(float depth) {
  float n = light.shadow_params.z, f = light.shadow_params.w;
  if (shadow_kind() == SHADOW_ORTHOGRAPHIC) return n + depth * (f - n);
  return 2.0 * f * n / ((f + n) - (2.0 * depth - 1.0) * (f - n));
}

float shadow_depth_of_distance(float distance) {
  float n = light.shadow_params.z, f = light.shadow_params.w;
  return ((f + n) / (f - n) - 2.0 * f * n / ((f - n) * distance)) * 0.5 + 0.5;
}

// Where a receiver point falls in its map: 2-D maps give (uv, depth); cube maps give (direction, depth).
struct ShadowCoord {
  vec3 at;        // uv and 0, or the cube direction
  float depth;    // reference depth-buffer value
  float distance; // receiver distance along the map's axis
  bool outside;   // outside a 2-D map's frustum
};

ShadowCoord shadow_coord(vec3 p) {
  ShadowCoord c;
  c.outside = false;
  if (shadow_kind() == SHADOW_CUBE) {
    vec3 v = p - light.shadow_origin.xyz;  // into the light's frame, in which the cube was rendered
    c.at = vec3(dot(v, light.axis_x.xyz), dot(v, light.axis_y.xyz), dot(v, light.axis_z.xyz));
    c.distance = max(abs(c.at.x), max(abs(c.at.y), abs(c.at.z)));
    c.depth = shadow_depth_of_distance(c.distance);
    return c;
  }
  vec4 clip = light.shadow_view_projection * vec4(p, 1.0);
  vec3 ndc = clip.xyz / clip.w;
  c.outside = clip.w <= 0.0 || any(greaterThan(abs(ndc.xy), vec2(1.0)));
  c.at = vec3(ndc.xy * 0.5 + 0.5, 0.0);
  c.depth = min(ndc.z * 0.5 + 0.5, 1.0);
  c.distance = shadow_linear_depth(c.depth);
  return c;
}

// The lookup position moved by `offset` texels in the map.
vec3 shadow_offset(ShadowCoord c, vec2 offset) {
  float texel = 2.0 / light.shadow_soft.y;
  if (shadow_kind() != SHADOW_CUBE) return c.at + vec3(offset * (0.5 * texel), 0.0);
  vec3 axis = normalize(c.at);
  vec3 u = normalize(cross(axis, abs(axis.z) < 0.9 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0)));
  vec3 v = cross(axis, u);
  return c.at + (offset.x * u + offset.y * v) * (texel * c.distance);
}

float shadow_compare(vec3 at, float depth) {
  if (shadow_kind() == SHADOW_CUBE) return texture(shadow_map_cube, vec4(at, depth));
  return texture(shadow_map_2d, vec3(at.xy, depth));
}

float shadow_depth_of(float distance) {
  float n = light.shadow_params.z, f = light.shadow_params.w;
  return shadow_kind() == SHADOW_ORTHOGRAPHIC ? (distance - n) / (f - n) : shadow_depth_of_distance(distance);
}

// Receiver distance along the axis of the map (cube: of the face) that the lookup `at` falls in: a tap near a
// cube edge may land in the neighbouring face, whose depths measure another axis.
float shadow_axis_distance(ShadowCoord c, vec3 at) {
  return shadow_kind() == SHADOW_CUBE ? max(abs(at.x), max(abs(at.y), abs(at.z))) : c.distance;
}

float shadow_raw_depth(vec3 at) {
  if (shadow_kind() == SHADOW_CUBE) return texture(shadow_depth_cube, at).r;
  return texture(shadow_depth_2d, at.xy).r;
}

vec2 vogel_disk(int i, float rotation) {
  float r = sqrt((float(i) + 0.5) / float(SHADOW_TAPS));
  float phi = float(i) * 2.39996323 + rotation;
  return r * vec2(cos(phi), sin(phi));
}

// `p` is the receiver, already offset along its normal against acne; `slope` is the tangent of the angle between
// its normal and the light. Filter taps away from p compare against the receiver's plane there, not against p's
// depth, or a sloped receiver would shadow itself: the margin is the plane's worst-case depth change.
float shadow_visibility_at(vec3 p, float slope, uint pixel_hash, float share) {
  ShadowCoord c = shadow_coord(p);
  if (c.outside) return shadow_kind() == SHADOW_ORTHOGRAPHIC ? 1.0 : 0.0;
  // World size of one texel at the receiver (orthographic maps: constant).
  float texel_world = light.shadow_params.y * (shadow_kind() == SHADOW_ORTHOGRAPHIC ? 1.0 : c.distance);
  if (share <= 0.0) return shadow_compare(c.at, c.depth);

  float rotation = 6.2831853 * hash_to_unit(pixel_hash);
  // Blocker search over the penumbra a blocker halfway to the light would cast.
  float halfway = shadow_kind() == SHADOW_ORTHOGRAPHIC ? 0.25 * (light.shadow_params.w - light.shadow_params.z) : 1.0;
  float search = clamp(0.5 * share * halfway / texel_world, 1.0, MAX_FILTER_TEXELS);
  float blockers = 0.0, blocker_distance = 0.0;
  for (int i = 0; i < SHADOW_TAPS; ++i) {
    vec2 offset = search * vogel_disk(i, rotation);
    vec3 at = shadow_offset(c, offset);
    float distance = shadow_linear_depth(shadow_raw_depth(at));
    if (distance < shadow_axis_distance(c, at) - (length(offset) * slope + 1.0) * texel_world) {
      blockers += 1.0;
      blocker_distance += distance;
    }
  }
  if (blockers == 0.0) return 1.0;
  blocker_distance /= blockers;
  float penumbra = shadow_kind() == SHADOW_ORTHOGRAPHIC
                       ? share * (c.distance - blocker_distance)
                       : share * (c.distance - blocker_distance) / max(blocker_distance, 1e-6);
  float radius = min(0.5 * penumbra / texel_world, MAX_FILTER_TEXELS);
  if (radius < 0.5) return shadow_compare(c.at, c.depth);
  float visible = 0.0;
  for (int i = 0; i < SHADOW_TAPS; ++i) {
    vec2 offset = radius * vogel_disk(i, rotation);
    vec3 at = shadow_offset(c, offset);
    float margin = length(offset) * slope * texel_world;
    visible += shadow_compare(at, shadow_depth_of(shadow_axis_distance(c, at) - margin));
  }
  return visible / float(SHADOW_TAPS);
}

// Receiver offset along the geometric normal, in shadow-map texels at the receiver (normal-offset shadows).
vec3 shadow_receiver(vec3 x, vec3 geometric, vec3 to_light) {
  if (dot(geometric, to_light) < 0.0) geometric = -geometric;
  int kind = int(light.shadow_params.x);
  float texel = light.shadow_params.y;
  if (kind != SHADOW_ORTHOGRAPHIC) texel *= length(x - light.shadow_origin.xyz);
  return x + geometric * (settings.shadow_bias * texel);
}

// The visibility estimate of this sample. Light samples below the receiver's horizon cannot reach it and carry
// no information: visibility counts samples above it only, divided by the probability of landing there, so
// the average over samples is the visibility of the part of the light the receiver sees (unbiased), and a
// receiver whose plane cuts the light is not darkened by the part behind it. Sample 0 is the light's centre,
// not a random point: when that is below the horizon it counts as visible (a bias of at most 1/samples).
// `decorrelation` varies the filter's kernel rotation between receivers (e.g. a pixel hash). `filtered` false
// gives one hard lookup toward this sample's light point: unbiased over the samples all the same, and without
// the filter's receiver-plane margin, which lets light through at grazing angles.
float shadow_visibility(vec3 x, vec3 n, vec3 geometric, float above_horizon, uint decorrelation, bool filtered) {
  int kind = shadow_kind();
  if (kind == SHADOW_NONE) return 1.0;
  vec3 to_light = kind == SHADOW_ORTHOGRAPHIC ? light.shadow_origin.xyz : normalize(light.shadow_origin.xyz - x);
  bool random_sample = light.shadow_soft.z != 0.0;
  if (kind != SHADOW_ORTHOGRAPHIC && above_horizon < 1.0 && random_sample) {
    if (dot(n, to_light) <= 0.0) return 0.0;
  } else {
    above_horizon = 1.0;
  }
  if (dot(n, to_light) <= 0.0) return 1.0;  // the centre, below the horizon
  float cos_theta = max(abs(dot(geometric, to_light)), 0.1);
  float slope = sqrt(1.0 - cos_theta * cos_theta) / cos_theta;
  uint hash = decorrelation ^ floatBitsToUint(light.shadow_soft.z);
  float share = filtered ? light.shadow_soft.x : 0.0;
  return shadow_visibility_at(shadow_receiver(x, geometric, to_light), slope, hash, share) / max(above_horizon, 1e-3);
}
