// Screen-Space VPL Propagation: parameters, VPL and cluster buffers, and clustered visibility.
// Mirror of the parameter block: native/src/passes/ssvp/ssvp_pass.h, SsvpParams.
#include "common/emitter_occluders.glsl"
#include "ssvp/ssvp_shared.glsl"

const float SSVP_PI = 3.14159265358979;
const int RSM_ORTHOGRAPHIC = 1;

layout(std140, binding = 5) uniform SsvpParams {
  vec4 light_origin;  // xyz the RSM's eye (sun: direction towards it), w kind
  int first_count, second_count, cluster_count, tiles_per_axis;
  int rsm_face_size, rsm_faces_x, rsm_faces_y, paraboloid_size;
  float rsm_texel_factor, texels_per_vpl, epsilon, length_scale;
  float w1, w2, paraboloid_far;
  int second_per_cluster, bounces, pattern_rotation;
  int first_offset;  // while sampling: where this light's VPLs start (first_count: how many)
  float texels_per_capped_vpl;  // RSM texels / all the sample's first-bounce VPLs: the area that caps them
  int image_width;              // while shading: the tile's
  uint check_random;            // while shading: which pairs Ray Checks draws, new every sample
} ssvp;

struct Vpl {
  vec4 position_cluster;  // xyz position, w the cluster whose paraboloid map shadows it
  vec4 normal;            // xyz unit normal of its emitting side, w the area of the surface it stands for
  vec4 flux;              // rgb flux (W), w 1 if the VPL exists (0: its sample hit no surface)
};

struct Cluster {
  vec4 position_first;  // xyz the paraboloid map's centre, w the first member's index
  vec4 normal_count;    // xyz the map's axis (the members' normal sum, normalised), w member count
  vec4 tangent;
  vec4 bitangent;
};

layout(std430, binding = 6) readonly buffer SsvpPoints { vec2 points[]; };
layout(std430, binding = 7) buffer FirstVpls { Vpl first_vpls[]; };
layout(std430, binding = 8) readonly buffer Clusters { Cluster clusters[]; };
layout(std430, binding = 9) buffer SecondVpls { Vpl second_vpls[]; };

// Position in a cluster's frame: z along its normal.
vec3 cluster_local(int c, vec3 x) {
  vec3 d = x - clusters[c].position_first.xyz;
  return vec3(dot(d, clusters[c].tangent.xyz), dot(d, clusters[c].bitangent.xyz), dot(d, clusters[c].normal_count.xyz));
}

ivec2 paraboloid_texel(vec2 disk_point) {
  return clamp(ivec2((disk_point * 0.5 + 0.5) * float(ssvp.paraboloid_size)), ivec2(0), ivec2(ssvp.paraboloid_size - 1));
}

// Irradiance a VPL gives the receiver x (normal n), unshadowed but for emitters in between: flux / pi G,
// G = max(n_p . l, 0) max(n . -l, 0) / max(d^2, eps^2). G is capped at pi / A, A the area of the surface the VPL
// stands for: then a VPL never gives more irradiance than that surface's exitance flux / A, which a point light
// next to a receiver would exceed without bound. The cap loosens as VPLs grow more numerous (A shrinks), so the
// result still converges to the VPLs' limit, and it leaves the cosines' falloff alone (inside a sphere,
// G = 1 / 4R^2 everywhere: no cap applies).
vec3 vpl_irradiance(Vpl vpl, vec3 x, vec3 n) {
  if (vpl.flux.w == 0.0) return vec3(0.0);
  vec3 to_vpl = vpl.position_cluster.xyz - x;
  float d2 = dot(to_vpl, to_vpl);
  vec3 l = to_vpl * inversesqrt(max(d2, 1e-30));
  float g = max(dot(n, l), 0.0) * max(dot(vpl.normal.xyz, -l), 0.0) / max(d2, ssvp.epsilon * ssvp.epsilon);
  g = min(g, SSVP_PI / max(vpl.normal.w, 1e-30));
  if (g > 0.0 && emitter_between(vpl.position_cluster.xyz, x, 5e-5 * ssvp.length_scale)) return vec3(0.0);
  return vpl.flux.rgb * (g / SSVP_PI);
}
