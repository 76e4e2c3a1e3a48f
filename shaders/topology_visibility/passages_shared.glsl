// The direction bins of the passages between clusters and of the occluders inside them (native/topology/
// passages.h, occluders.h), shared by visibility.glsl, the estimates on the CPU and their upload
// (native/topology/shared_glsl.h includes this file into C++ with GLM). Written in the common subset of GLSL and
// C++; PASSAGES_INLINE is `inline` in C++.
// Bins per side of the octahedral map of directions; a passage or an occluder cell holds this squared.
#define TOPOLOGY_PASSAGE_BINS_PER_SIDE 8

#ifndef PASSAGES_INLINE
#define PASSAGES_INLINE
#endif

// The octahedral map (Engelhardt and Dachsbacher 2008) of a nonzero direction to [-1, 1]^2, and back to a unit
// direction: every bin of a square grid on it holds about the same solid angle.
PASSAGES_INLINE vec2 octahedral_from_direction(vec3 d) {
  float l1 = abs(d.x) + abs(d.y) + abs(d.z);
  float u = d.x / l1, v = d.y / l1;
  if (d.z < 0.0f) {
    float folded_u = (1.0f - abs(v)) * (u < 0.0f ? -1.0f : 1.0f);
    v = (1.0f - abs(u)) * (v < 0.0f ? -1.0f : 1.0f);
    u = folded_u;
  }
  return vec2(u, v);
}

PASSAGES_INLINE vec3 direction_from_octahedral(vec2 e) {
  float u = e.x, v = e.y;
  float z = 1.0f - abs(u) - abs(v);
  if (z < 0.0f) {
    float folded_u = (1.0f - abs(v)) * (u < 0.0f ? -1.0f : 1.0f);
    v = (1.0f - abs(u)) * (v < 0.0f ? -1.0f : 1.0f);
    u = folded_u;
  }
  return normalize(vec3(u, v, z));
}

// The bin of a nonzero direction d on a `side` x `side` square grid over the octahedral map.
PASSAGES_INLINE int octahedral_bin(vec3 d, int side) {
  vec2 e = octahedral_from_direction(d);
  int i = min(int((e.x * 0.5f + 0.5f) * float(side)), side - 1);
  int j = min(int((e.y * 0.5f + 0.5f) * float(side)), side - 1);
  return j * side + i;
}

// The unit direction at (s, t) in [0, 1]^2 of bin `bin` of a `side` x `side` grid ((0.5, 0.5): its centre;
// octahedral_bin's inverse).
PASSAGES_INLINE vec3 octahedral_bin_direction(int bin, int side, float s, float t) {
  return direction_from_octahedral(vec2((float(bin % side) + s) / float(side) * 2.0f - 1.0f,
                                        (float(bin / side) + t) / float(side) * 2.0f - 1.0f));
}

PASSAGES_INLINE int topology_passage_bin(vec3 d) { return octahedral_bin(d, TOPOLOGY_PASSAGE_BINS_PER_SIDE); }

PASSAGES_INLINE vec3 topology_passage_bin_direction(int bin, float s, float t) {
  return octahedral_bin_direction(bin, TOPOLOGY_PASSAGE_BINS_PER_SIDE, s, t);
}

// A passage keeps two tables of shares: light whose source or receiver lies within this many voxels of its plane
// (on the slats of blinds or the sill inside the opening, which see through it more freely than what lies beyond)
// takes the near table, other light the far one.
#define TOPOLOGY_PASSAGE_NEAR_VOXELS 2.0f

// The table (0 far, 1 near) of light between points at signed distances side_p and side_x from a passage's plane.
PASSAGES_INLINE int topology_passage_table(float side_p, float side_x, float voxel) {
  return min(abs(side_p), abs(side_x)) < TOPOLOGY_PASSAGE_NEAR_VOXELS * voxel ? 1 : 0;
}

// behind_occluder's reach for a light inside the receiver's cluster: no gate, the whole segment.
#define TOPOLOGY_WITHIN_CLUSTER 3.0e38f

// Whether a light at `offset` from a receiver (the light's position less the receiver's; `distance` its length,
// which the caller has) lies behind the plane of the surface that stands for its direction bin inside the
// receiver's cell (topology::Occluders::Hit's normal and plane) by more than two voxels, the distance the cell's
// surface point and the receiver may lie apart. reach: how far toward the light the segment enters the receiver's
// cluster through a gate (TOPOLOGY_WITHIN_CLUSTER for a light inside it); that point must lie behind the plane
// too: a surface about as far is the gate's frame (the wall around a doorway), which the gate's rectangle already
// accounts for.
PASSAGES_INLINE bool behind_occluder(vec3 normal, float plane, vec3 offset, float distance, float reach,
                                     float voxel) {
  return dot(normal, offset) * min(reach / distance, 1.0f) < plane - 2.0f * voxel;
}
