// The direction bins of the passages between clusters (native/topology/passages.h), shared by visibility.glsl and
// the estimate on the CPU (native/topology/passages.cpp includes this file into C++ with GLM). Written in the
// common subset of GLSL and C++; PASSAGES_INLINE is `inline` in C++.
// Bins per side of the octahedral map of directions; a passage holds this squared.
#define TOPOLOGY_PASSAGE_BINS_PER_SIDE 8

#ifndef PASSAGES_INLINE
#define PASSAGES_INLINE
#endif

// The bin of unit direction d: the octahedral map (Engelhardt and Dachsbacher 2008), which gives every bin about
// the same solid angle, on a TOPOLOGY_PASSAGE_BINS_PER_SIDE square grid.
PASSAGES_INLINE int topology_passage_bin(vec3 d) {
  float l1 = abs(d.x) + abs(d.y) + abs(d.z);
  float u = d.x / l1, v = d.y / l1;
  if (d.z < 0.0f) {
    float folded_u = (1.0f - abs(v)) * (u < 0.0f ? -1.0f : 1.0f);
    v = (1.0f - abs(u)) * (v < 0.0f ? -1.0f : 1.0f);
    u = folded_u;
  }
  int n = TOPOLOGY_PASSAGE_BINS_PER_SIDE;
  int i = min(int((u * 0.5f + 0.5f) * float(n)), n - 1);
  int j = min(int((v * 0.5f + 0.5f) * float(n)), n - 1);
  return j * n + i;
}

// The unit direction at (s, t) in [0, 1]^2 of bin `bin` ((0.5, 0.5): its centre; topology_passage_bin's inverse).
PASSAGES_INLINE vec3 topology_passage_bin_direction(int bin, float s, float t) {
  int n = TOPOLOGY_PASSAGE_BINS_PER_SIDE;
  float u = (float(bin % n) + s) / float(n) * 2.0f - 1.0f;
  float v = (float(bin / n) + t) / float(n) * 2.0f - 1.0f;
  float z = 1.0f - abs(u) - abs(v);
  if (z < 0.0f) {
    float folded_u = (1.0f - abs(v)) * (u < 0.0f ? -1.0f : 1.0f);
    v = (1.0f - abs(u)) * (v < 0.0f ? -1.0f : 1.0f);
    u = folded_u;
  }
  return normalize(vec3(u, v, z));
}
