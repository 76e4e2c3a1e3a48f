// The visibility gate test of the topology method, shared by the shaders (shaders/topology_visibility/) and the
// CPU (native/topology/shared_glsl.h includes this file into C++ with GLM). Written in the common subset of GLSL
// and C++; GATES_INLINE is `inline` in C++.
// The most clusters a walk through gates visits, the first included (topology_visibility, cpu reaches()).
#define TOPOLOGY_WALK_CLUSTERS 8

#ifndef GATES_INLINE
#define GATES_INLINE
#endif

// Noel and Biri 2014, Sec. V.C, Fig. 11: the cone from a light at p through a gate holds x when the segment p-x
// crosses the gate's plane inside the gate. A gate here is the rectangle around the opening between its clusters
// (native/topology/segmentation.h, fit_gates_to_boundaries): centre, unit normal, unit axis u in its plane, and
// half extents along u and along cross(normal, u).
GATES_INLINE bool in_gate_cone(vec3 p, vec3 centre, vec3 normal, vec3 u, float half_u, float half_v, vec3 x) {
  float side_p = dot(p - centre, normal);
  float side_x = dot(x - centre, normal);
  if (!(side_p * side_x < 0.0f)) return false;
  vec3 crossing = p + (x - p) * (side_p / (side_p - side_x));
  vec3 offset = crossing - centre;
  return abs(dot(offset, u)) <= half_u && abs(dot(offset, cross(normal, u))) <= half_v;
}

// How far from x the segment p-x crosses the gate's plane (in_gate_cone holds): where the light enters x's cluster
// when this gate ends the walk.
GATES_INLINE float gate_entry_distance(vec3 p, vec3 centre, vec3 normal, vec3 x) {
  float side_p = dot(p - centre, normal);
  float side_x = dot(x - centre, normal);
  return length(x - p) * (side_x / (side_x - side_p));
}
