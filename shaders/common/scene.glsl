// Scene tables shared by every pass that draws geometry (bindings: native/src/gpu_scene.h).
struct Instance {
  mat4 object_to_world;
  mat4 normal_to_world;
};
struct Material {
  vec4 base_color_alpha;
  vec4 emission_threshold;  // rgb emitted radiance, a cut-out threshold
  ivec4 flags;              // x: has base-colour texture, y: texture alpha is a cut-out
};
layout(std430, binding = 1) readonly buffer Instances { Instance instances[]; };
layout(std430, binding = 2) readonly buffer InstanceLists { uint instance_lists[]; };
layout(std430, binding = 3) readonly buffer Materials { Material materials[]; };

layout(location = 0) uniform mat4 u_view_projection;
layout(location = 1) uniform int u_instance_offset;
layout(location = 2) uniform int u_material;
layout(binding = 0) uniform sampler2D u_base_color_texture;
layout(binding = 16) uniform sampler2D u_emission_texture;  // white when the material has none

#ifdef BOUNCE_VERTEX_SHADER
Instance current_instance() { return instances[instance_lists[u_instance_offset + gl_InstanceID]]; }
#endif

// Base colour and alpha at a surface point. The texture sample is 1 when the material has none. Level 0, as Cycles
// and the CPU rays sample it: the jittered samples average a texture over each pixel already, and the mip chain
// is not only blurred but biased (Sponza's albedo 7 % above Cycles' DiffCol with it, 1 % without).
vec4 surface_base_color(vec2 uv) {
  Material m = materials[u_material];
  vec4 texel = textureLod(u_base_color_texture, uv, 0.0);
  float alpha = m.flags.y != 0 ? m.base_color_alpha.a * texel.a : m.base_color_alpha.a;
  return vec4(m.base_color_alpha.rgb * texel.rgb, alpha);
}

vec3 surface_emission(vec2 uv) {
  return materials[u_material].emission_threshold.rgb * textureLod(u_emission_texture, uv, 0.0).rgb;
}

bool surface_is_cut_out(float alpha) { return alpha < materials[u_material].emission_threshold.a; }
