// One light in radiometric units (native/include/bounce/bounce.h, BounceLight) and its unshadowed irradiance.
// Mirror: native/src/passes/direct/light_block.h.
const float PI = 3.14159265358979;

const int LIGHT_POINT = 0;
const int LIGHT_SPOT = 1;
const int LIGHT_SUN = 2;
const int LIGHT_AREA_RECT = 3;
const int LIGHT_AREA_ELLIPSE = 4;
const int LIGHT_AREA_TRIANGLE = 5;

const int SHADOW_NONE = 0;
const int SHADOW_ORTHOGRAPHIC = 1;
const int SHADOW_PERSPECTIVE = 2;
const int SHADOW_CUBE = 3;

layout(std140, binding = 4) uniform LightBlock {
  vec4 position_type;         // xyz position, w type
  vec4 axis_x;
  vec4 axis_y;
  vec4 axis_z;                // the light shines along -axis_z
  vec4 intensity;             // rgb: W/sr (point, spot), W/m^2 (sun), W/m^2/sr (area)
  vec4 shape;                 // radius, half size x, half size y, spot half angle
  vec4 spot_sun;              // spot blend, spot cos falloff (0/1), sun angle, -
  vec4 triangle;              // triangle: its second and third corners in (axis_x, axis_y) from position
  vec4 shadow_origin;         // xyz: this sample's point on the light (cube, perspective) or direction (sun)
  mat4 shadow_view_projection;
  vec4 shadow_params;         // x kind, y texel size factor, z near, w far
  vec4 shadow_soft;           // x this sample's share of the light: its diameter (sun: 2 tan(half angle)), y map size
} light;

int light_type() { return int(light.position_type.w); }

// Blender/Cycles spot cone: smoothstep over the blend region inside the cone edge; Blender 3.x multiplies
// the result by cos(phi) too.
float spot_attenuation(vec3 from_light) {
  float cos_phi = dot(from_light, -light.axis_z.xyz);
  float cos_half = cos(light.shape.w);
  if (cos_phi <= cos_half) return 0.0;
  float smooth_width = (1.0 - cos_half) * light.spot_sun.x;
  float t = cos_phi - cos_half;
  float factor = smooth_width > 0.0 ? smoothstep(0.0, smooth_width, t) : 1.0;
  return light.spot_sun.y != 0.0 ? factor * cos_phi : factor;
}

#include "common/lambert_shared.glsl"

// The emitter outline of this light in world space.
int area_light_polygon(out vec3 vertices[MAX_POLYGON]) {
  if (light_type() == LIGHT_AREA_TRIANGLE) {
    vertices[0] = light.position_type.xyz;
    vertices[1] = light.position_type.xyz + light.triangle.x * light.axis_x.xyz + light.triangle.y * light.axis_y.xyz;
    vertices[2] = light.position_type.xyz + light.triangle.z * light.axis_x.xyz + light.triangle.w * light.axis_y.xyz;
    return 3;
  }
  return emitter_polygon(light.position_type.xyz, light.axis_x.xyz * light.shape.y, light.axis_y.xyz * light.shape.z,
                         light_type() == LIGHT_AREA_RECT, vertices);
}

// Unshadowed irradiance at x with shading normal n, per colour channel. `above_horizon` is the fraction of the
// light (area: of its surface; point and spot: of the ball of their radius) on the lit side of the receiver's
// tangent plane: the probability that a uniform light sample can reach the receiver at all.
vec3 light_irradiance(vec3 x, vec3 n, out float above_horizon) {
  above_horizon = 1.0;
  int type = light_type();
  if (type == LIGHT_SUN) return light.intensity.rgb * max(dot(n, light.axis_z.xyz), 0.0);
  vec3 to_light = light.position_type.xyz - x;
  if (type == LIGHT_POINT || type == LIGHT_SPOT) {
    float r = light.shape.x;
    if (r > 0.0) {
      float t = clamp(r - dot(n, to_light), 0.0, 2.0 * r);  // height of the ball's cap below the plane
      above_horizon = 1.0 - t * t * (3.0 * r - t) / (4.0 * r * r * r);
    }
    float d2 = dot(to_light, to_light);
    vec3 l = to_light * inversesqrt(max(d2, 1e-30));
    float falloff = max(dot(n, l), 0.0) / (d2 + r * r);
    if (type == LIGHT_SPOT) falloff *= spot_attenuation(-l);
    return light.intensity.rgb * falloff;
  }
  // Area: only the side facing -axis_z emits; a triangle (an emissive mesh's) emits from both, as in Cycles, but
  // not onto its own plane: Lambert's formula there is the limit from above (pi L), not the surface's own 0.
  if (type != LIGHT_AREA_TRIANGLE && dot(-to_light, -light.axis_z.xyz) <= 0.0) return vec3(0.0);
  if (type == LIGHT_AREA_TRIANGLE &&
      abs(dot(to_light, light.axis_z.xyz)) <= 1e-4 * (length(light.triangle.xy) + length(light.triangle.zw)))
    return vec3(0.0);
  vec3 polygon[MAX_POLYGON];
  int count = area_light_polygon(polygon);
  for (int i = 0; i < count; ++i) polygon[i] -= x;
  vec3 clipped[MAX_POLYGON];
  int clipped_count = clip_to_horizon(polygon, count, n, clipped);
  if (clipped_count < 3) return vec3(0.0);
  float area = planar_polygon_area(polygon, count);  // 0 where float32 collapses the outline (see lambert_shared)
  above_horizon = area > 0.0 ? clamp(planar_polygon_area(clipped, clipped_count) / area, 0.0, 1.0) : 1.0;
  return light.intensity.rgb * polygon_projected_solid_angle(clipped, clipped_count, n);
}
