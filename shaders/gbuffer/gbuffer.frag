// G-buffer: what the lighting passes need to know of the visible surface at each pixel.
#include "common/scene.glsl"

in vec3 v_world_position;
in vec3 v_world_normal;
in vec2 v_uv;

layout(location = 3) uniform vec3 u_camera_position;
layout(location = 4) uniform mat4 u_world_to_view;
layout(location = 5) uniform int u_orthographic;
layout(location = 6) uniform vec3 u_camera_forward;

layout(location = 0) out vec4 out_albedo;    // rgb albedo, a coverage
layout(location = 1) out vec4 out_normal;    // shading normal, facing the camera
layout(location = 2) out vec4 out_position;  // world position, w view depth
layout(location = 3) out vec4 out_emission;
layout(location = 4) out vec4 out_geometric_normal;

void main() {
  vec4 base = surface_base_color(v_uv);
  if (surface_is_cut_out(base.a)) discard;

  // Surfaces are two-sided, as in Cycles: normals are flipped towards the viewer.
  vec3 to_eye = u_orthographic != 0 ? -u_camera_forward : u_camera_position - v_world_position;
  vec3 geometric = normalize(cross(dFdx(v_world_position), dFdy(v_world_position)));
  if (any(isnan(geometric))) geometric = normalize(v_world_normal);
  if (dot(geometric, to_eye) < 0.0) geometric = -geometric;
  vec3 shading = normalize(v_world_normal);
  if (any(isnan(shading))) shading = geometric;
  if (dot(shading, geometric) < 0.0) shading = -shading;

  out_albedo = vec4(base.rgb, 1.0);
  out_normal = vec4(shading, 0.0);
  out_position = vec4(v_world_position, -(u_world_to_view * vec4(v_world_position, 1.0)).z);
  out_emission = vec4(surface_emission(v_uv), 0.0);
  out_geometric_normal = vec4(geometric, 0.0);
}
