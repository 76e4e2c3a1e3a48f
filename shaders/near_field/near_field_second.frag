// The second bounce's share of what the distance clamp takes (Kollig and Keller 2006's compensation, one level
// deeper; cpu/near_field.h): the surface y that a pixel's near-field ray met within the clamp reflects, toward
// it, its own first-bounce irradiance E1(y) times albedo (1 - d^2 / c^2) (the reflectance the CPU traced). E1(y)
// is the first bounce of the pixel that sees y, or of the pixel itself where it faces as y does (the source index
// the CPU found): the VPLs' first bounce there (both bounces less the second) and its near field. Where no pixel
// has it (-1), the CPU estimated it from the VPLs (cpu::UnseenFirstBounce) and gives the light itself.
layout(binding = 8) uniform sampler2D reflectance;
layout(binding = 9) uniform isampler2D source;
layout(binding = 10) uniform sampler2D indirect_light;  // irradiance / pi, both bounces
layout(binding = 11) uniform sampler2D second_bounce;   // irradiance / pi
layout(binding = 12) uniform sampler2D near_field;      // irradiance / pi of the first bounce
layout(binding = 13) uniform sampler2D unseen;          // irradiance / pi of the second bounce, where index < 0

layout(location = 0) out vec4 out_second;  // irradiance / pi

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  int index = texelFetch(source, pixel, 0).r;
  if (index < 0) {
    out_second = vec4(texelFetch(unseen, pixel, 0).rgb, 0.0);
    return;
  }
  int width = textureSize(source, 0).x;
  ivec2 q = ivec2(index % width, index / width);
  vec3 first = texelFetch(indirect_light, q, 0).rgb - texelFetch(second_bounce, q, 0).rgb +
               texelFetch(near_field, q, 0).rgb;
  out_second = vec4(texelFetch(reflectance, pixel, 0).rgb * max(first, vec3(0.0)), 0.0);
}
