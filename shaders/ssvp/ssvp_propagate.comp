// Second-bounce VPLs (Sec. II-B): cluster c's VPLs sit at uniform points of the unit disk of its paraboloid
// map (the map's image is that disk, so no sample is wasted outside it). A disk point p stands for the solid angle
// (pi / M) 4 / (1 + |p|^2)^2 (the map's Jacobian) seen from the cluster's centre, hence for the surface patch of
// area A = solid angle x d^2 / cos there. The VPL at that surface y carries what the patch reflects of the
// cluster's first-bounce light: albedo x A x the irradiance its members give y, each member i from its own
// position and normal, flux_i / pi x cos_i cos_y / d_i^2 (capped as the shading caps it), so the M VPLs together
// carry what the surfaces seen from the centre reflect. The paper renders the map "in the same fashion as the
// RSM", which leaves the transfer open; treating the cluster as one light at its centre (the members' cosine
// lobes from there) let light through wherever the centre floats away from its members: a cluster mixing a
// sunlit roof and a courtyard floor lit the galleries under the roof from mid-air, 4-7x too bright. The map
// still decides which surfaces the centre sees. The VPLs are then clustered on their own, and each is shadowed
// by its cluster's map.
#include "ssvp/ssvp_common.glsl"

layout(local_size_x = 64) in;
#include "common/dispatch.glsl"

const float MIN_COSINE = 1e-2;  // a surface seen edge-on stands for a long strip; its area is capped there

layout(binding = 13) uniform sampler2DArray paraboloid_position;
layout(binding = 14) uniform sampler2DArray paraboloid_normal;
layout(binding = 15) uniform sampler2DArray paraboloid_albedo;

void main() {
  uint g = linear_invocation();
  if (g >= uint(ssvp.second_count)) return;
  int c = int(g) / ssvp.second_per_cluster;
  int m = int(g) % ssvp.second_per_cluster;
  vec2 p = points[ssvp.first_count + m];
  ivec3 texel = ivec3(paraboloid_texel(p), c);
  vec4 albedo = texelFetch(paraboloid_albedo, texel, 0);
  Vpl vpl;
  vpl.position_cluster = vec4(0.0);
  vpl.normal = vec4(0.0, 0.0, 1.0, 0.0);
  vpl.flux = vec4(0.0);
  if (albedo.a > 0.0) {
    Cluster cluster = clusters[c];
    float solid_angle = SSVP_PI / float(ssvp.second_per_cluster) * ssvp_paraboloid_solid_angle_density(p);
    vec3 y = texelFetch(paraboloid_position, texel, 0).xyz;
    vec3 n = texelFetch(paraboloid_normal, texel, 0).xyz;
    vec3 irradiance = vec3(0.0);
    int first = int(cluster.position_first.w);
    int count = int(cluster.normal_count.w);
    for (int i = first; i < first + count; ++i) irradiance += vpl_irradiance(first_vpls[i], y, n);
    vpl.position_cluster = vec4(y, float(c));  // until SsvpPass::cluster_second_bounce clusters it
    // The surface this VPL stands for: its solid angle seen from the centre, at its distance and slant.
    vec3 to_centre = cluster.position_first.xyz - y;
    float d2 = dot(to_centre, to_centre);
    float area = solid_angle * d2 / max(dot(n, to_centre) * inversesqrt(max(d2, 1e-30)), MIN_COSINE);
    vpl.normal = vec4(n, area);
    vpl.flux = vec4(albedo.rgb * irradiance * area, 1.0);
    if (any(isnan(vpl.flux)) || any(isinf(vpl.flux))) vpl.flux = vec4(0.0);
  }
  second_vpls[g] = vpl;
}
