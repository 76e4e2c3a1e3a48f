// Indirect visibility from the topology of the empty space (Noel and Biri 2014) on the GPU: the voxels' visibility
// clusters as a 3-D texture, the gates of each cluster as buffers (native/src/passes/topology_visibility/). A
// light at p in cluster A reaches x in cluster B when A == B, or when the segment p-x crosses gates from A to B
// inside their rectangles (Fig. 11), as cpu::TopologyRenderer's rule; where that renderer casts shadow rays (between
// clusters no gates join) this weighs the light by the passages, and inside a cluster by the occluders.
#include "topology_visibility/gates_shared.glsl"
#include "topology_visibility/passages_shared.glsl"

const uint TOPOLOGY_NO_CLUSTER = 0xFFFFFFFFu;
// topology_voxels_clear: how far off its surface each end starts, and how much of either end the march skips, in
// voxels.
#define TOPOLOGY_MARCH_LIFT 1.5
#define TOPOLOGY_MARCH_SKIP 0.5

// Per padded grid cell: its visibility cluster (topology::voxel_clusters_split_at_gates), TOPOLOGY_NO_CLUSTER on
// solid cells and the padding.
layout(binding = 20) uniform usampler3D topology_clusters;

layout(std140, binding = 6) uniform TopologyGrid {
  vec4 origin_voxel;  // xyz the corner of padded cell (0, 0, 0), w the voxel size
  ivec4 dims;         // xyz padded cells per axis, w the cluster count (0: no topology)
} topology_grid;

struct TopologyGate {
  vec4 centre_half_u;  // centre, half extent along u
  vec4 normal_half_v;  // normal, half extent along cross(normal, u)
  vec4 axis_u;
  uvec4 clusters;  // xy: the clusters either side; z: 1 for a second opening (topology::Gate::needs_ray)
};
layout(std430, binding = 10) readonly buffer TopologyGates { TopologyGate topology_gates[]; };
// [3 c], [3 c + 1]: the first index and the count of cluster c's gates in the rest of the array; [3 c + 2]: its
// component of the graph the gates make (Topology::component).
layout(std430, binding = 11) readonly buffer TopologyClusterGates { uint topology_cluster_gates[]; };
// The passages between clusters no chain of gates joins (topology::Passages; native/topology/passages.h): first,
// per pair of clusters [a * cluster count + b], 0 or 1 + the index of its passage; then per passage, as float
// bits, its rectangle (centre and half extent along u, normal and half extent along cross(normal, u), u) and the
// share of the light that passes by the bin of the direction from the pair's lower cluster to its higher, the far
// table then the near one (topology_passage_table). A single 0 when there are none.
layout(std430, binding = 13) readonly buffer TopologyPassages { uint topology_passages[]; };

float topology_passage(uint from, vec3 p, uint to, vec3 x) {
  if (topology_passages.length() < 2) return 0.0;
  uint count = uint(topology_grid.dims.w);
  uint index = topology_passages[from * count + to];
  if (index == 0u) return 0.0;
  uint bins = uint(TOPOLOGY_PASSAGE_BINS_PER_SIDE * TOPOLOGY_PASSAGE_BINS_PER_SIDE);
  uint base = count * count + (index - 1u) * (12u + 2u * bins);
  vec4 rectangle[3];
  for (uint i = 0u; i < 3u; ++i)
    rectangle[i] = uintBitsToFloat(uvec4(topology_passages[base + 4u * i], topology_passages[base + 4u * i + 1u],
                                         topology_passages[base + 4u * i + 2u], topology_passages[base + 4u * i + 3u]));
  if (!in_gate_cone(p, rectangle[0].xyz, rectangle[1].xyz, rectangle[2].xyz, rectangle[0].w, rectangle[1].w, x))
    return 0.0;
  int bin = topology_passage_bin(normalize(from < to ? x - p : p - x));
  int table = topology_passage_table(dot(p - rectangle[0].xyz, rectangle[1].xyz),
                                     dot(x - rectangle[0].xyz, rectangle[1].xyz), topology_grid.origin_voxel.w);
  return uintBitsToFloat(topology_passages[base + 12u + uint(table) * bins + uint(bin)]);
}

// The occluders inside clusters (topology::Occluders; native/topology/occluders.h): per padded grid cell 0 or 1 +
// its slot (a single cell when there are none); per slot and direction bin a word: the distance from the cell's
// surface to the plane of the surface that stands for the bin, along its normal (Occluders::Hit::plane), as a
// half float (bits 0-15), that surface's normal in the
// octahedral map at 6 bits per coordinate (bits 16-27), the share of the bin it hides in 15ths (bits 28-31).
layout(binding = 22) uniform usampler3D topology_occluder_cells;
layout(std430, binding = 14) readonly buffer TopologyOccluders { uint topology_occluders[]; };

uint topology_cluster_in(ivec3 cell) {
  if (any(lessThan(cell, ivec3(0))) || any(greaterThanEqual(cell, topology_grid.dims.xyz))) return TOPOLOGY_NO_CLUSTER;
  return texelFetch(topology_clusters, cell, 0).r;
}

ivec3 topology_cell(vec3 p) {
  return ivec3(floor((p - topology_grid.origin_voxel.xyz) / topology_grid.origin_voxel.w));
}

// The cluster of the first empty voxel from p along the unit d, in steps of half a voxel up to `voxels` voxels;
// TOPOLOGY_NO_CLUSTER when there is none.
uint topology_cluster_along(vec3 p, vec3 d, float voxels) {
  float voxel = topology_grid.origin_voxel.w;
  for (float step = 0.5; step <= voxels; step += 0.5) {
    uint cluster = topology_cluster_in(topology_cell(p + step * voxel * d));
    if (cluster != TOPOLOGY_NO_CLUSTER) return cluster;
  }
  return TOPOLOGY_NO_CLUSTER;
}

// The cluster of a surface point p on the side of its unit normal n (Topology::cluster_at, Side::Front): the
// first empty voxel from p along n within two voxels, else p's own voxel, else its nearest empty neighbour on
// n's side. TOPOLOGY_NO_CLUSTER outside the grid or walled in.
uint topology_cluster_at(vec3 p, vec3 n) {
  float voxel = topology_grid.origin_voxel.w;
  uint along = topology_cluster_along(p, n, 2.0);
  if (along != TOPOLOGY_NO_CLUSTER) return along;
  ivec3 cell = topology_cell(p);
  uint nearest = topology_cluster_in(cell);
  if (nearest != TOPOLOGY_NO_CLUSTER) return nearest;
  float best = 1e30;
  vec3 centre = topology_grid.origin_voxel.xyz + (vec3(cell) + 0.5) * voxel;
  for (int i = 0; i < 27; ++i) {
    ivec3 o = ivec3(i % 3, (i / 3) % 3, i / 9) - 1;
    if (o == ivec3(0) || dot(vec3(o), n) <= 0.0) continue;
    uint cluster = topology_cluster_in(cell + o);
    float d = distance(centre + vec3(o) * voxel, p);
    if (cluster != TOPOLOGY_NO_CLUSTER && d < best) {
      nearest = cluster;
      best = d;
    }
  }
  return nearest;
}

// The cluster of a pixel's surface point p, seen along the unit `to_eye` (toward the camera) with the G-buffer's
// normal n: the first empty voxel back along the camera's ray within four voxels, which the ray came through, else
// topology_cluster_at's. Where a floor meets a wall, the voxels along the floor's normal lie in the wall's solid
// voxels and the nearest empty neighbour may be beyond the wall or outside the room: those pixels lost the room's
// light, and the blur spread the loss over a band. The lit one of two rooms split by a wall, 64 samples, against
// the paper's FLC (no visibility, no leak there): 0.962 along the normal, 0.970 within two voxels back along the
// ray, 0.978 within four or eight.
uint topology_cluster_seen(vec3 p, vec3 n, vec3 to_eye) {
  uint seen = topology_cluster_along(p, to_eye, 4.0);
  return seen != TOPOLOGY_NO_CLUSTER ? seen : topology_cluster_at(p, n);
}

// How much of a light at p a surface inside x's cluster leaves to the receiver x: where the surface that rays from
// x's cell along the bin of p - x meet (topology::Occluders) has p, and the point `reach` from x toward p where the
// light enters the cluster, behind its plane (behind_occluder), the share of the bin's rays that miss it.
float topology_unoccluded(vec3 p, vec3 x, float reach) {
  ivec3 cell = topology_cell(x);
  if (any(lessThan(cell, ivec3(0))) || any(greaterThanEqual(cell, textureSize(topology_occluder_cells, 0))))
    return 1.0;
  uint slot = texelFetch(topology_occluder_cells, cell, 0).r;
  if (slot == 0u) return 1.0;
  vec3 offset = p - x;
  float distance = length(offset);
  if (!(distance > 0.0)) return 1.0;
  uint bins = uint(TOPOLOGY_PASSAGE_BINS_PER_SIDE * TOPOLOGY_PASSAGE_BINS_PER_SIDE);
  int bin = topology_passage_bin(offset / distance);
  uint word = topology_occluders[(slot - 1u) * bins + uint(bin)];
  float plane = unpackHalf2x16(word).x;
  if (isinf(plane)) return 1.0;  // no surface
  vec3 normal =
      direction_from_octahedral(vec2(float((word >> 16) & 63u), float((word >> 22) & 63u)) / 63.0 * 2.0 - 1.0);
  if (!behind_occluder(normal, plane, offset, distance, reach, topology_grid.origin_voxel.w)) return 1.0;
  return 1.0 - float(word >> 28) / 15.0;
}

// Whether the segment between p and x, each lifted off its surface along its unit normal, meets no solid voxel:
// the GPU's stand-in for the shadow ray that confirms a walk through a second opening on the CPU, whose rectangle
// may stand in front of a wall (a dome's, beside a doorway) or span other clusters (Sponza's arcades), and that
// decides between joined clusters where no chain of rectangles holds the segment.
bool topology_voxels_clear(vec3 p, vec3 n_p, vec3 x, vec3 n_x) {
  float voxel = topology_grid.origin_voxel.w;
  vec3 from = p + TOPOLOGY_MARCH_LIFT * voxel * n_p, to = x + TOPOLOGY_MARCH_LIFT * voxel * n_x;
  float length_px = distance(from, to);
  if (!(length_px < 3.0e38)) return false;  // not finite: no march can say
  vec3 d = (to - from) / max(length_px, 1e-20);
  for (float t = TOPOLOGY_MARCH_SKIP * voxel; t < length_px - TOPOLOGY_MARCH_SKIP * voxel; t += 0.5 * voxel)
    if (topology_cluster_in(topology_cell(from + t * d)) == TOPOLOGY_NO_CLUSTER) return false;
  return true;
}

// How much of a light at p in cluster `from` reaches x in cluster `to`, as on the CPU (cpu::reaches), its light
// entering the empty space `light_reach` from x at most (TOPOLOGY_WITHIN_CLUSTER: at p; for a light in thin geometry,
// where the ray of its ray map entered it, the ray having seen to the thin geometry): a light without a cluster lights
// nothing (the CPU casts it a shadow ray; there are no rays here); a receiver without one has no visibility information
// and takes every light but those a surface inside the cluster hides (as does the light's own cluster); clusters no
// chain of gates joins pass their passage's share in the direction p-x where the segment crosses its rectangle;
// otherwise, when the segment p-x crosses a chain of gates from `from` to `to`, each inside its rectangle, found by a
// breadth-first walk through at most TOPOLOGY_WALK_CLUSTERS clusters, what the surfaces between x and the last gate
// leave (topology_unoccluded), and when it does not, all of it where the voxels between p and x are clear and none
// where they are not. A chain through a second opening holds only where the voxels between p and x are clear, and then
// passes all of the light, as a shadow ray's word does on the CPU. A chain through first openings may end in a passage
// into `to` (the ground outside a window, in clusters gated to the one its blinds' passage starts from), which passes
// its share.
float topology_visibility(uint from, vec3 p, vec3 n_p, uint to, vec3 x, vec3 n_x, float light_reach) {
  if (from == TOPOLOGY_NO_CLUSTER) return 0.0;
  if (to == TOPOLOGY_NO_CLUSTER || from == to) return topology_unoccluded(p, x, light_reach);
  uint walk[TOPOLOGY_WALK_CLUSTERS];
  bool via_second[TOPOLOGY_WALK_CLUSTERS];
  walk[0] = from;
  via_second[0] = false;
  uint walked = 1u;
  // The march depends on the segment alone: chains through second openings and the joined clusters' last word
  // share one.
  bool marched = false, clear = false;
  for (uint head = 0u; head < walked; ++head) {
    uint cluster = walk[head];
    if (!via_second[head]) {
      float passage = topology_passage(cluster, p, to, x);
      if (passage > 0.0) return passage;
    }
    uint first = topology_cluster_gates[3u * cluster], count = topology_cluster_gates[3u * cluster + 1u];
    for (uint i = first; i < first + count; ++i) {
      TopologyGate gate = topology_gates[topology_cluster_gates[i]];
      uint beyond = gate.clusters.x == cluster ? gate.clusters.y : gate.clusters.x;
      bool visited = false;
      for (uint k = 0u; k < walked; ++k) visited = visited || walk[k] == beyond;
      if (visited || !in_gate_cone(p, gate.centre_half_u.xyz, gate.normal_half_v.xyz, gate.axis_u.xyz,
                                   gate.centre_half_u.w, gate.normal_half_v.w, x))
        continue;
      bool second = via_second[head] || gate.clusters.z != 0u;
      if (beyond == to) {
        if (second) {
          if (!marched) clear = topology_voxels_clear(p, n_p, x, n_x);
          marched = true;
          if (clear) return 1.0;
          continue;
        }
        return topology_unoccluded(
            p, x, min(light_reach, gate_entry_distance(p, gate.centre_half_u.xyz, gate.normal_half_v.xyz, x)));
      }
      if (walked < uint(TOPOLOGY_WALK_CLUSTERS)) {
        via_second[walked] = second;
        walk[walked++] = beyond;
      }
    }
  }
  // No chain of rectangles holds the segment, yet gates join the clusters: the rectangle stands for a boundary
  // that is an opening (a doorway, a window), and light that crosses the boundary beside it meets its frame; but
  // the boundary between clusters of one open space (the air around objects standing on open ground, a court's
  // arcades) is no opening, and light crosses all of it. The voxels decide, as a shadow ray does where the CPU
  // cannot tell (cpu::reaches gives these pairs nothing; a ray for each would weigh on its gathering). The open
  // ground under one sun, 240x135, 16 samples, seeds 0-1, first bounce against Cycles: 0.922 (left third 0.78)
  // with the gates alone, 1.02 (0.99) with the voxels; Sponza's middle third 0.891/0.915 -> 1.00/1.02.
  if (topology_cluster_gates[3u * from + 2u] != topology_cluster_gates[3u * to + 2u]) return 0.0;
  return (marched ? clear : topology_voxels_clear(p, n_p, x, n_x)) ? 1.0 : 0.0;
}
