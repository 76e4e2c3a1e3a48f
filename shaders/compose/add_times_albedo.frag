// Adds albedo x a light texture (irradiance / pi) into one accumulation target: the AOVs beyond the eight the
// compose pass writes at once.
layout(binding = 1) uniform sampler2D g_albedo;
layout(binding = 12) uniform sampler2D light_over_pi;

layout(location = 0) out vec4 out_value;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 albedo = texelFetch(g_albedo, pixel, 0);
  out_value = albedo.a == 0.0 ? vec4(0.0) : vec4(albedo.rgb * texelFetch(light_over_pi, pixel, 0).rgb, 0.0);
}
