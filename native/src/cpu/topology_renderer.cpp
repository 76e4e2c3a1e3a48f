#include "cpu/topology_renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "common/parallel.h"
#include "cpu/camera_ray.h"
#include "cpu/direct_light.h"
#include "cpu/near_field.h"
#include "cpu/random.h"
#include "radiometry.h"
#include "sample_schedule.h"
#include "sampling.h"
#include "topology/shared_glsl.h"

namespace bounce::cpu {
namespace {

using topology::kNoNode;

constexpr int kDepthSlices = 16;           // clustered shading's exponential depth slices (Olsson et al. 2012)
constexpr float kBackgroundDepth = 1e10f;  // Blender's Depth pass value where nothing is hit
constexpr float kEmitterMargin = 1e-4f;    // of the scene's radius: the surfaces a segment ends on (FLC's margin)
enum Purpose : uint64_t {
  kDirectLight = 21,
  kVplResampling = 22,
  kVplSample = 23,
  kNearField = 24,
  kRayChecks = 25,
  kUnseenNearField = 26
};

// ---- View samples -----------------------------------------------------------------------------------------

struct ViewSample {
  Surface surface;
  glm::vec3 origin{0.0f}, direction{0.0f};  // the primary ray
  float t = 0.0f;                           // its hit distance
  float depth = kBackgroundDepth;           // along the view axis
  uint32_t cluster = kNoNode;
  bool hit = false;
};

// A light whose visibility at a pixel the clusters and gates decided (not a shadow ray), for Ray Checks.
struct RuledPair {
  uint32_t vpl;
  glm::vec3 irradiance;  // unshadowed
  float share;           // the rule's verdict
};

bool in_gate_cone(glm::vec3 p, const topology::Gate& gate, glm::vec3 x) {
  return topology::shared::in_gate_cone(p, gate.centre, gate.normal, gate.axis_u, gate.half_u, gate.half_v, x);
}

}  // namespace

// Each cluster's gates; light from one cluster reaches another through gates only within its component
// (Topology::joined).
struct ClusterGraph {
  std::vector<std::vector<uint32_t>> gates_of;  // per cluster

  explicit ClusterGraph(const topology::Topology& topo) : gates_of(topo.cluster_count) {
    for (std::size_t g = 0; g < topo.gates.size(); ++g)
      for (uint32_t c : topo.gates[g].clusters)
        if (c < topo.cluster_count) gates_of[c].push_back(uint32_t(g));
  }
};

namespace {

// Whether the method lets a VPL at p in cluster `from` light x in cluster `to`: its own cluster without a test,
// another when the segment p-x crosses a chain of gates from `from` to `to`, each inside its rectangle (Fig. 11
// for one gate), found by a breadth-first walk as topology_visibility (shaders/topology_visibility/visibility.glsl)
// does: the paper's single gate test let light through any of the cluster's gates, toward any cluster. A view
// sample outside every cluster has no visibility information and counts every light here (the shading casts it
// a shadow ray). A chain found only through gates that need a ray (Gate::needs_ray) lets the light through if a
// shadow ray does.
// first_gates: the gates of `from` the walk may leave it by (all of them when empty; light assignment passes those
// whose cones meet a group of view samples). entry, when the light reaches x through gates: how far from x the
// segment crosses the last (gate_entry_distance).
enum class Reach : uint8_t { kNo, kYes, kIfRayClear };
Reach reaches(const topology::Topology& topo, const ClusterGraph& graph, uint32_t from, glm::vec3 p, uint32_t to,
              glm::vec3 x, float& entry, std::span<const uint32_t> first_gates = {}) {
  if (from == kNoNode) return Reach::kNo;
  if (to == kNoNode || to == from) return Reach::kYes;
  bool passed_ray_gates = false;
  for (const bool with_ray_gates : {false, true}) {
    if (with_ray_gates && !passed_ray_gates) break;
    std::array<uint32_t, TOPOLOGY_WALK_CLUSTERS> walk{from};
    std::size_t walked = 1;
    for (std::size_t head = 0; head < walked; ++head) {
      const uint32_t cluster = walk[head];
      for (uint32_t g : head == 0 && !first_gates.empty() ? first_gates : std::span(graph.gates_of[cluster])) {
        const topology::Gate& gate = topo.gates[g];
        const uint32_t beyond = gate.clusters[0] == cluster ? gate.clusters[1] : gate.clusters[0];
        if (std::find(walk.begin(), walk.begin() + walked, beyond) != walk.begin() + walked ||
            !in_gate_cone(p, gate, x))
          continue;
        // Walked again with these gates only when the segment crosses one: otherwise the walk would be the same.
        if (gate.needs_ray() && !with_ray_gates) {
          passed_ray_gates = true;
          continue;
        }
        if (beyond == to) {
          entry = topology::shared::gate_entry_distance(p, gate.centre, gate.normal, x);
          return with_ray_gates ? Reach::kIfRayClear : Reach::kYes;
        }
        if (walked < walk.size()) walk[walked++] = beyond;
      }
    }
  }
  return Reach::kNo;
}

// How the method's visibility decides whether a VPL in cluster `from` lights a point in cluster `to`.
enum class Test : uint8_t {
  kNone,       // the same cluster (the occluders inside it), or no indirect visibility at all
  kGates,      // reaches(): the segment must cross gates into the point's cluster
  kShadowRay,  // a shadow ray: the Shadow Rays mode, and where the topology cannot tell (below)
};
Test visibility_test(int topology_visibility, const topology::Topology& topo, uint32_t from, uint32_t to) {
  if (topology_visibility == 2) return Test::kNone;
  if (topology_visibility == 1) return Test::kShadowRay;
  if (from == to && from != kNoNode) return Test::kNone;
  // A point or a VPL outside every cluster (outside the grid, or where the voxels in front of it are solid for
  // the lookup's few steps: a sill under the bottom rail of a blind at 256^3, whose light the room lost when such
  // VPLs counted as walled in): the topology says nothing of its visibility, and lighting it with every light let
  // a closed room's edges glow with the light of the room beside it. Clusters no chain of gates joins: the opening
  // between them may be narrower than a voxel (blinds whose gaps the grid closes, which kept out half of a sunlit
  // room's indirect light) or not be there at all (a solid wall). The renderer casts those rays only for VPLs
  // whose light reached a probe that way (lit_by_ray).
  if (from == kNoNode || to == kNoNode || !topo.joined(from, to)) return Test::kShadowRay;
  return Test::kGates;
}

// The share of a light at `offset` from a receiver that the receiver's occluders (topology::unoccluded) leave to it:
// within a cluster, and through gates, whose rectangles bound where the segment enters the receiver's cluster, not
// what it meets inside it (blocks in a room stood between the lights of gated clusters and their receivers: the
// open box kept 1.068 of the shadow rays' indirect light); all of it where a shadow ray decided.
float occluder_share(Test test, Reach reach, float entry, std::span<const topology::Occluders::Hit> hits,
                     glm::vec3 offset, float voxel) {
  if (test == Test::kNone) return topology::unoccluded(hits, offset, TOPOLOGY_WITHIN_CLUSTER, voxel);
  if (test == Test::kGates && reach == Reach::kYes) return topology::unoccluded(hits, offset, entry, voxel);
  return 1.0f;
}

// Whether an emitter drawn this sample stands between a VPL at p and a receiver at x where no shadow ray decided:
// the clusters' rule for emitters (shaders/common/emitter_occluders.glsl). A panel hanging a voxel below a ceiling
// shares the room's cluster and lies within the occluders' slack of the ceiling above it, whose VPLs lit the room
// through it: the Cornell box lit by its panel had 1.10 of Cycles' first bounce (shadow rays: 1.00).
bool emitter_hides(std::span<const EmitterOccluder> emitters, Test test, Reach reach, glm::vec3 p, glm::vec3 x,
                   float margin) {
  if (emitters.empty() || test == Test::kShadowRay || reach == Reach::kIfRayClear) return false;
  return emitter_between(emitters, p, x, margin);
}

// Whether a bounding sphere may hold points of that cone: the sphere must reach beyond the gate's plane and
// within the right circular cone from p enclosing the gate's bounding sphere.
bool sphere_meets_gate_cone(glm::vec3 p, const topology::Gate& gate, glm::vec3 centre, float radius) {
  const float side_p = glm::dot(p - gate.centre, gate.normal);
  if (side_p == 0.0f) return false;
  const float beyond = -glm::dot(centre - gate.centre, gate.normal) * (side_p > 0.0f ? 1.0f : -1.0f);
  if (beyond < -radius) return false;
  const glm::vec3 axis = gate.centre - p, to_sphere = centre - p;
  const float axis_length = glm::length(axis), distance = glm::length(to_sphere);
  if (distance <= radius || axis_length <= gate.radius) return true;
  const float cone = std::asin(std::min(1.0f, gate.radius / axis_length));
  const float sphere = std::asin(std::min(1.0f, radius / distance));
  const float angle = std::acos(std::clamp(glm::dot(axis, to_sphere) / (axis_length * distance), -1.0f, 1.0f));
  return angle <= cone + sphere;
}

// A distinct, bright colour per visibility cluster.
glm::vec3 cluster_colour(uint32_t cluster) {
  const uint64_t h = mix(cluster + 1);
  const float hue = float(h & 0xFFFF) / 65536.0f;
  const glm::vec3 k = glm::abs(glm::fract(glm::vec3(hue) + glm::vec3(0.0f, 2.0f / 3.0f, 1.0f / 3.0f)) * 6.0f - 3.0f);
  return 0.25f + 0.75f * glm::clamp(k - 1.0f, 0.0f, 1.0f);
}

struct Assignment {
  uint32_t vpl;
  Test test;
  uint32_t first_gate = 0, first_gates = 0;  // kGates: the range of the group's gate list its walk may start by
  bool near_emitter = false;  // an emitter's bounding sphere meets the segments from the VPL to the group
};

// An emitter drawn this sample, bounded by a sphere.
struct EmitterSphere {
  glm::vec3 centre;
  float radius;
};
std::vector<EmitterSphere> emitter_spheres(std::span<const EmitterOccluder> emitters) {
  std::vector<EmitterSphere> spheres;
  for (const EmitterOccluder& e : emitters) {
    const glm::vec3 a(e.a), b(e.b), c(e.c), centre = (a + b + c) / 3.0f;
    spheres.push_back({centre, std::max({glm::length(a - centre), glm::length(b - centre), glm::length(c - centre)})});
  }
  return spheres;
}
// Whether an emitter may cross a segment from p to a point of the sphere (centre, radius): the segments all lie
// within `radius` of the segment from p to the centre.
bool near_emitter(std::span<const EmitterSphere> emitters, glm::vec3 p, glm::vec3 centre, float radius) {
  const glm::vec3 d = centre - p;
  const float length2 = glm::dot(d, d);
  return std::any_of(emitters.begin(), emitters.end(), [&](const EmitterSphere& e) {
    const float t = length2 > 0.0f ? std::clamp(glm::dot(e.centre - p, d) / length2, 0.0f, 1.0f) : 0.0f;
    return glm::length(e.centre - (p + t * d)) <= radius + e.radius;
  });
}
struct GroupLights {
  std::vector<Assignment> lights;    // by interleaving subset (Interleaving), each in VPL order
  std::vector<uint32_t> gates;       // the assignments' first gates
  std::vector<uint32_t> subset_end;  // per interleaving subset, the end of its lights

  std::span<const Assignment> of_subset(uint32_t k) const {
    const uint32_t begin = k == 0 ? 0 : subset_end[k - 1];
    return std::span(lights).subspan(begin, subset_end[k] - begin);
  }
};

// A sphere or a gate (a rectangle) of the Topology pass, drawn where the primary ray meets it before the surface.
struct Glyph {
  glm::vec3 centre{0.0f};
  float radius = 0.0f;  // a sphere's; around a gate's rectangle
  const topology::Gate* gate = nullptr;
  glm::vec4 colour{0.0f};  // alpha: opacity over what lies behind
};

// Distance along the unit ray to the glyph, or infinity.
float hit_glyph(const Glyph& glyph, glm::vec3 origin, glm::vec3 dir) {
  const glm::vec3 to_centre = glyph.centre - origin;
  if (const topology::Gate* gate = glyph.gate) {
    const float facing = glm::dot(dir, gate->normal);
    if (std::abs(facing) < 1e-8f) return std::numeric_limits<float>::infinity();
    const float t = glm::dot(to_centre, gate->normal) / facing;
    const glm::vec3 offset = origin + dir * t - glyph.centre;
    const bool inside = std::abs(glm::dot(offset, gate->axis_u)) <= gate->half_u &&
                        std::abs(glm::dot(offset, glm::cross(gate->normal, gate->axis_u))) <= gate->half_v;
    return t > 0.0f && inside ? t : std::numeric_limits<float>::infinity();
  }
  const float along = glm::dot(to_centre, dir);
  const float d2 = glm::dot(to_centre, to_centre) - along * along, r2 = glyph.radius * glyph.radius;
  if (d2 > r2) return std::numeric_limits<float>::infinity();
  const float t = along - std::sqrt(r2 - d2);
  return t > 0.0f ? t : std::numeric_limits<float>::infinity();
}

// The Topology pass (paper Figs. 2, 5, 9): surfaces in the colour of their visibility cluster, the skeleton's
// nodes as spheres (segmented nodes: a quarter of their maximal ball, in their cluster's colour), gates as
// rectangles.
// Drawn from the first sample's rays, through the pixel centres.
void draw_topology_pass(const topology::Topology& topo, const BounceSettings& settings, const BounceCamera& camera,
                        int x0, int y0, int width, int height, const std::vector<ViewSample>& view,
                        std::vector<glm::vec4>& image) {
  std::vector<Glyph> glyphs;
  if (settings.topology_show_skeleton) {
    const float dot = 0.5f * float(topo.grid.shape.voxel_size);
    for (std::size_t n = 0; n < topo.skeleton.position.size(); ++n)
      glyphs.push_back({topo.skeleton.position[n], dot, nullptr, {0.9f, 0.9f, 0.9f, 1.0f}});
    for (std::size_t m = 0; m < topo.segmented.original.size(); ++m) {
      const uint32_t node = topo.segmented.original[m];
      glyphs.push_back({topo.skeleton.position[node], std::max(dot, 0.25f * topo.skeleton.radius[node]), nullptr,
                        glm::vec4(cluster_colour(topo.cluster_of[m]), 1.0f)});
    }
  }
  if (settings.topology_show_gates)
    for (const topology::Gate& gate : topo.gates)
      glyphs.push_back({gate.centre, gate.radius, &gate, {0.2f, 0.45f, 1.0f, 0.7f}});
  // Screen rectangles of the glyphs' bounding boxes, so each row tests only the glyphs that may cover it.
  const glm::dmat4 world_to_clip =
      glm::dmat4(glm::make_mat4(camera.projection)) * glm::dmat4(glm::make_mat4(camera.world_to_view));
  std::vector<glm::ivec4> rects(glyphs.size());
  for (std::size_t g = 0; g < glyphs.size(); ++g) {
    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    bool behind = false;
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 sign((corner & 1) ? 1.0f : -1.0f, (corner & 2) ? 1.0f : -1.0f, (corner & 4) ? 1.0f : -1.0f);
      const std::optional<glm::dvec2> pixel = image_point(
          world_to_clip, glm::dvec3(glyphs[g].centre + sign * glyphs[g].radius), camera.width, camera.height);
      if (!pixel) {
        behind = true;
        break;
      }
      lo = glm::min(lo, *pixel);
      hi = glm::max(hi, *pixel);
    }
    rects[g] = behind ? glm::ivec4(0, 0, width - 1, height - 1)
                      : glm::ivec4(std::clamp(int(std::floor(lo.x)) - x0, -1, width),
                                   std::clamp(int(std::floor(lo.y)) - y0, -1, height),
                                   std::clamp(int(std::ceil(hi.x)) - x0, -1, width),
                                   std::clamp(int(std::ceil(hi.y)) - y0, -1, height));
  }
  parallel_for(std::size_t(height), 0, 1, [&](std::size_t row) {
    const int y = int(row);
    std::vector<std::pair<float, uint32_t>> hits;
    for (int x = 0; x < width; ++x) {
      const std::size_t i = row * std::size_t(width) + std::size_t(x);
      const ViewSample& v = view[i];
      glm::vec4 colour(0.0f);
      if (settings.topology_show_clusters && v.hit && v.cluster != kNoNode) {
        const float shade = 0.35f + 0.65f * std::abs(glm::dot(v.surface.normal, v.direction));
        colour = glm::vec4(cluster_colour(v.cluster) * shade, 1.0f);
      }
      hits.clear();
      const float surface_t = v.hit ? v.t : std::numeric_limits<float>::infinity();
      for (std::size_t g = 0; g < glyphs.size(); ++g) {
        const glm::ivec4& r = rects[g];
        if (x < r.x || x > r.z || y < r.y || y > r.w) continue;
        const float t = hit_glyph(glyphs[g], v.origin, v.direction);
        if (t < surface_t) hits.emplace_back(t, uint32_t(g));
      }
      std::sort(hits.begin(), hits.end());
      for (auto it = hits.rbegin(); it != hits.rend(); ++it) {  // back to front
        const glm::vec4 c = glyphs[it->second].colour;
        colour = glm::vec4(glm::mix(glm::vec3(colour), glm::vec3(c), c.a), c.a + colour.a * (1.0f - c.a));
      }
      image[i] = colour;
    }
  });
}

// The irradiance a view sample gathered from the VPLs: all of it, and the second bounce's part.
struct Gathered {
  glm::vec3 all{0.0f}, second{0.0f};
};

// Interleaved sampling (Keller and Heidrich 2001; Segovia et al. 2006), as Forward Light Cuts' tiling does on the
// GPU: in each n x n block of pixels, each pixel gathers one of n^2 subsets of the VPLs (every n^2-th VPL, whose
// light it takes n^2 times), so gathering costs about 1 / n^2 of every VPL per pixel. Recombining takes, over the
// pixels of a (2n - 1)^2 window that see the same surface (visibility cluster, normal, plane), the mean of each
// subset's estimates and the mean over the subsets found. The VPLs are one systematic draw per sample (resample),
// so a subset of every n^2-th draw is a stratum of it and the n^2 subsets together are the whole draw: where the
// window finds them all, the pixel's light is the whole draw's; a pixel that finds fewer (an edge, a thin object)
// keeps those strata's estimate, noisier and nearly unbiased (the open box's mean moved by 0.03 %).
struct Interleaving {
  int n;
  uint32_t subsets;

  explicit Interleaving(int32_t setting) : n(std::clamp(setting, 1, 4)), subsets(uint32_t(n * n)) {}

  uint32_t subset(int x, int y) const { return uint32_t(x % n + n * (y % n)); }

  Gathered recombine(std::span<const ViewSample> view, std::span<const Gathered> gathered, int width, int height,
                     int x0, int y0, std::size_t i) const {
    if (subsets == 1) return gathered[i];
    // Neighbours on the same surface: their normals within about 18 degrees, their points within 1 % of the
    // distance to the camera of the pixel's tangent plane.
    constexpr float kMinCosine = 0.95f, kPlaneSlack = 0.01f;
    std::array<Gathered, 16> sum{};
    std::array<int, 16> count{};
    const ViewSample& v = view[i];
    const int column = int(i % std::size_t(width)), row = int(i / std::size_t(width));
    for (int dy = 1 - n; dy < n; ++dy)
      for (int dx = 1 - n; dx < n; ++dx) {
        const int x = column + dx, y = row + dy;
        if (x < 0 || y < 0 || x >= width || y >= height) continue;
        const std::size_t j = std::size_t(y) * std::size_t(width) + std::size_t(x);
        const ViewSample& u = view[j];
        if (j != i &&
            (!u.hit || u.cluster != v.cluster ||
             glm::dot(u.surface.shading_normal, v.surface.shading_normal) < kMinCosine ||
             std::abs(glm::dot(u.surface.position - v.surface.position, v.surface.shading_normal)) > kPlaneSlack * v.t))
          continue;
        const uint32_t k = subset(x0 + x, y0 + y);
        sum[k].all += gathered[j].all;
        sum[k].second += gathered[j].second;
        ++count[k];
      }
    Gathered mean;
    int found = 0;
    for (uint32_t k = 0; k < subsets; ++k)
      if (count[k] > 0) {
        mean.all += sum[k].all / float(count[k]);
        mean.second += sum[k].second / float(count[k]);
        ++found;
      }
    mean.all /= float(found);
    mean.second /= float(found);
    return mean;
  }
};

}  // namespace

uint32_t TopologyRenderer::vpl_cluster(const Vpl& vpl) const {
  // A VPL's cluster must be reachable from it: one inside a block thinner than the lookup's steps (a light
  // inside a wall) would otherwise reach through to the room beyond.
  const float offset = scene_.ray_offset();
  const auto reachable = [&](glm::vec3 from, glm::vec3 to) {
    return scene_.clear_between(from + vpl.normal * offset, to);
  };
  return topologies_.latest()->cluster_at(vpl.position, vpl.normal, topology::Topology::Side::Front, reachable);
}

void TopologyRenderer::prepare_vpls(std::span<const BounceLight> lights, const SceneLights& scene_lights,
                                    const BounceSettings& settings, uint64_t seed, std::span<const Probe> probes,
                                    const ClusterGraph& graph) {
  const LightKinds kinds{scene_lights.lamp_count(), scene_lights.world_count()};
  const std::span<const EmitterOccluder> emitters = scene_lights.emitter_occluders();
  // Candidates: kCandidatesPerVpl times the VPLs wanted, traced from the lights (a sun's over a disk the size of
  // the scene, so most land where the camera sees nothing: on a roof, outside a window).
  VplOptions options;
  options.bounces = std::max(settings.bounces, 1);
  const int wanted = std::max(settings.topology_vpls, 1);
  options.paths = (kCandidatesPerVpl * wanted + options.bounces - 1) / options.bounces;
  options.seed = seed;
  options.guides = guides_;
  const std::vector<double> path_weights = path_shares_.weights(lights, kinds, scene_.radius());
  options.path_weights = path_weights;
  options.kinds = kinds;
  options.world_guide = &world_guide_;
  options.world_table = &scene_lights;
  const std::vector<Vpl> candidates = trace_vpls(scene_, lights, options);
  std::vector<uint32_t> candidate_cluster(candidates.size());
  parallel_for(candidates.size(), 0, 64, [&](std::size_t i) { candidate_cluster[i] = vpl_cluster(candidates[i]); });
  // Importance: the light a candidate gives the probes under the mode's own visibility, so the VPLs go where their
  // light reaches what the camera sees (resampled with a defensive share, hence unbiased for the candidates'
  // image). Measured under the clusters' rule in every mode, as before, the Shadow Rays mode drew the light that
  // the rule loses (through blinds) only through the defensive share, and lost 18 % of a sunlit room's.
  const topology::Topology& topo = *topologies_.latest();
  const bool clusters_and_gates = settings.topology_visibility == 0;
  // With Ray Checks the image converges to the shadow rays', so the importance is theirs: under the rule, lights
  // that it keeps out and the checks let in came only through the defensive share, and their few heavy draws left
  // a render of 4 samples at 0.97 of the rays' light.
  const bool checked = clusters_and_gates && settings.topology_ray_checks > 0.0f;
  const auto voxel = float(topo.grid.shape.voxel_size);
  const float clamp = settings.topology_distance_clamp * scene_.radius();
  const float offset = scene_.ray_offset();
  const float emitter_margin = kEmitterMargin * scene_.radius();
  std::vector<float> importance(candidates.size(), 0.0f);
  std::vector<uint8_t> lit_by_ray(candidates.size(), 0);
  parallel_for(candidates.size(), 0, 64, [&](std::size_t i) {
    const Vpl& vpl = candidates[i];
    double sum = 0.0;
    for (const Probe& probe : probes) {
      const glm::vec3 light = probe.albedo * vpl_irradiance(vpl, probe.position, probe.normal, clamp);
      if (!(light.r + light.g + light.b > 0.0f)) continue;
      const auto clear = [&] {
        return scene_.clear_between(vpl.position + vpl.normal * offset, probe.position + probe.normal * offset);
      };
      const Test test = visibility_test(settings.topology_visibility, topo, candidate_cluster[i], probe.cluster);
      if (checked) {
        if (!clear()) continue;
        if (test == Test::kShadowRay) lit_by_ray[i] = 1;
        sum += double(light.r + light.g + light.b);
        continue;
      }
      Reach reach = Reach::kYes;
      float entry = 0.0f;
      if (test == Test::kGates) {
        reach = reaches(topo, graph, candidate_cluster[i], vpl.position, probe.cluster, probe.position, entry);
        if (reach == Reach::kNo || (reach == Reach::kIfRayClear && !clear())) continue;
      }
      if (test == Test::kShadowRay) {
        if (!clear()) continue;
        lit_by_ray[i] = 1;
      }
      if (clusters_and_gates && emitter_hides(emitters, test, reach, vpl.position, probe.position, emitter_margin))
        continue;
      const float share = clusters_and_gates ? occluder_share(test, reach, entry, probe.occluder_hits,
                                                              vpl.position - probe.position, voxel)
                                             : 1.0f;
      sum += double(share * (light.r + light.g + light.b));
    }
    importance[i] = float(sum);
  });
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (candidates[i].light < guides_.size()) guides_[candidates[i].light].learn(candidates[i].emission, importance[i]);
  for (EmissionGuide& guide : guides_) guide.update();
  path_shares_.learn(candidates, importance, path_weights, options.paths, kinds);
  world_guide_.learn(candidates, importance, kinds);
  world_guide_.update();
  Rng rng(seed, kVplResampling, 0);
  vpls_.clear();
  vpl_cluster_.clear();
  vpl_lit_by_ray_.clear();
  for (const Draw& draw : resample(importance, wanted, kUniformShare, rng.next())) {
    vpls_.push_back(candidates[draw.index]);
    vpls_.back().power *= draw.weight;
    vpl_cluster_.push_back(candidate_cluster[draw.index]);
    vpl_lit_by_ray_.push_back(lit_by_ray[draw.index]);
  }
}

bool TopologyRenderer::render(const GpuScene& scene, SceneLights& scene_lights, const BounceSettings& settings,
                              const BounceCamera& camera, const RenderCallbacks& callbacks, StageTimer& timer) {
  int x0 = camera.crop[0], y0 = camera.crop[1], x1 = camera.crop[2], y1 = camera.crop[3];
  if (x0 == 0 && y0 == 0 && x1 == 0 && y1 == 0) {
    x1 = camera.width;
    y1 = camera.height;
  }
  const int width = x1 - x0, height = y1 - y0;
  const std::size_t pixels = std::size_t(width) * std::size_t(height);
  const uint32_t seed = hash_combine(static_cast<uint32_t>(settings.seed), static_cast<uint32_t>(camera.frame));
  const glm::vec2 jitter_rotation(hash_to_unit(hash_combine(seed, 101)), hash_to_unit(hash_combine(seed, 102)));
  timer.reset();
  {
    StageScope scope(timer, Stage::TopologyPrecompute);
    scene_.sync(scene);
    if (!topologies_.get(scene_, settings, callbacks)) return false;
  }
  const topology::Topology& topo = *topologies_.latest();
  const ClusterGraph graph(topo);

  const glm::dmat4 world_to_view = glm::dmat4(glm::make_mat4(camera.world_to_view));
  const glm::dmat4 world_to_clip = glm::dmat4(glm::make_mat4(camera.projection)) * world_to_view;
  const glm::dmat4 clip_to_world = glm::inverse(world_to_clip);
  const float radius = scene_.radius();
  const float offset = scene_.ray_offset();
  const float clamp = settings.topology_distance_clamp * radius;
  const float emitter_margin = kEmitterMargin * radius;
  const ShadowRays direct_rays{scene_.bvh(), offset, 1, scene_.opaque(), settings.shadow_softness};
  const BounceWorld& world = scene.world();
  const WorldRadiance world_radiance(world, scene.texture_data(world.environment_texture));
  const float background_alpha = world.transparent ? 0.0f : 1.0f;
  const float background_seen = world.transparent || world.camera_hidden ? 0.0f : 1.0f;

  struct Sums {
    std::vector<glm::vec3> combined, direct, emission, albedo, normal, indirect, second;
    std::vector<float> depth, alpha;
  } sums;
  for (auto* v :
       {&sums.combined, &sums.direct, &sums.emission, &sums.albedo, &sums.normal, &sums.indirect, &sums.second})
    v->assign(pixels, glm::vec3(0.0f));
  sums.depth.assign(pixels, kBackgroundDepth);
  sums.alpha.assign(pixels, 0.0f);
  std::vector<glm::vec4> topology_image(pixels, glm::vec4(0.0f));
  std::vector<ViewSample> view(pixels);
  std::vector<glm::vec3> direct(pixels), indirect(pixels), second(pixels);
  std::vector<NearField> near(pixels);
  const bool two_bounces = settings.bounces >= 2;
  std::vector<Gathered> gathered(pixels), recombined(pixels);
  const Interleaving interleaving(settings.topology_interleaving);
  // One light in check_every; a share below one in 65,536 (the most VPLs) checks at most one a pixel.
  const int check_every = settings.topology_ray_checks > 0.0f
                              ? int(std::lround(std::clamp(1.0f / settings.topology_ray_checks, 1.0f, 65536.0f)))
                              : 0;

  auto make_frame = [&](int samples_done) {
    auto frame = std::make_shared<Frame>();
    frame->allocate(width, height, method_aovs(BOUNCE_METHOD_TOPOLOGY));
    const float scale = 1.0f / float(samples_done);
    auto put = [&](int aov, std::size_t i, const float* value, int channels) {
      std::copy(value, value + channels, frame->aovs[aov].data() + std::size_t(bounce_aov_channels(aov)) * i);
    };
    for (std::size_t i = 0; i < pixels; ++i) {
      const glm::vec4 combined(sums.combined[i] * scale, sums.alpha[i] * scale);
      put(BOUNCE_AOV_COMBINED, i, glm::value_ptr(combined), 4);
      for (auto [aov, sum] : {std::pair{BOUNCE_AOV_DIRECT, &sums.direct},
                              {BOUNCE_AOV_EMISSION, &sums.emission},
                              {BOUNCE_AOV_ALBEDO, &sums.albedo},
                              {BOUNCE_AOV_NORMAL, &sums.normal}}) {
        const glm::vec3 value = (*sum)[i] * scale;
        put(aov, i, glm::value_ptr(value), 3);
      }
      const glm::vec3 indirect_mean = sums.indirect[i] * scale;
      const glm::vec3 second_mean = sums.second[i] * scale;
      put(BOUNCE_AOV_INDIRECT, i, glm::value_ptr(indirect_mean), 3);
      put(BOUNCE_AOV_SECOND_BOUNCE, i, glm::value_ptr(second_mean), 3);
      put(BOUNCE_AOV_DEPTH, i, &sums.depth[i], 1);
      put(BOUNCE_AOV_TOPOLOGY, i, glm::value_ptr(topology_image[i]), 4);
    }
    // Each bounce clamped on its mean, not per sample, which biased dark corners up (Sponza's gallery: its second
    // bounce 1.14 of Cycles with each sample clamped, 1.06 with the rule alone).
    frame->clamp_negative_indirect();
    frame->info.nonfinite_pixels = frame->zero_nonfinite();
    frame->info.vpl_count = vpls_.size();
    frame->info.cluster_count = static_cast<int32_t>(topo.cluster_count);
    frame->info.main_light = -1;
    frame->info.width = width;
    frame->info.height = height;
    frame->info.samples = samples_done;
    timer.fill(frame->info);
    return frame;
  };

  callbacks.status("", 0.5f);
  SampleSchedule schedule(settings);
  int samples_done = settings.samples;
  for (int s = 0; s < settings.samples; ++s) {
    if (callbacks.cancelled()) return false;
    const std::vector<BounceLight>& lights = scene_lights.sample(scene, settings, static_cast<uint32_t>(s), seed);
    const std::span<const EmitterOccluder> emitters = scene_lights.emitter_occluders();
    // The lamps keep their indices from sample to sample (the world's directions and the emitters do not).
    if (s == 0) {
      guides_.assign(scene_lights.lamp_count(), EmissionGuide{});
      path_shares_.reset(scene_lights.lamp_count());
      world_guide_ = LandingGuide(scene_.bounds_min(), scene_.bounds_max());
      sky_guide_ = SkyGuide(scene_.bounds_min(), scene_.bounds_max());
    }
    const glm::vec2 u = s == 0 ? glm::vec2(0.5f) : r2_point(static_cast<uint32_t>(s), jitter_rotation);
    const glm::vec2 jitter = (u - 0.5f) * settings.filter_width;
    {
      StageScope scope(timer, Stage::TopologyPrimary);
      parallel_for(std::size_t(height), 0, 1, [&](std::size_t row) {
        for (int column = 0; column < width; ++column) {
          ViewSample& v = view[row * std::size_t(width) + std::size_t(column)];
          v = ViewSample{};
          const double ndc_x = (x0 + column + 0.5 + jitter.x) / camera.width * 2.0 - 1.0;
          const double ndc_y = (y0 + double(row) + 0.5 + jitter.y) / camera.height * 2.0 - 1.0;
          const CameraRay ray = camera_ray(clip_to_world, ndc_x, ndc_y);
          v.origin = ray.origin;
          v.direction = ray.direction;
          if (!std::isfinite(v.origin.x) || !std::isfinite(v.direction.x)) continue;
          const auto hit = scene_.intersect(v.origin, v.direction, 0.0f, ray.tmax);
          if (!hit) continue;
          v.hit = true;
          v.t = hit->t;
          v.surface = scene_.surface(*hit, v.direction);
          v.depth = static_cast<float>(-(world_to_view * glm::dvec4(glm::dvec3(v.surface.position), 1.0)).z);
          v.cluster = topo.cluster_at(v.surface.position, v.surface.normal, topology::Topology::Side::Front);
        }
      });
    }
    {
      // New VPLs every sample, so the image converges; sample 0 keeps one set for a seed (the viewport's still
      // frames repeat).
      StageScope scope(timer, Stage::TopologyVpls);
      std::vector<Probe> probes;
      Rng rng(seed, kVplSample, uint64_t(s));
      for (int py = 0; py < kProbesPerAxis; ++py)
        for (int px = 0; px < kProbesPerAxis; ++px) {
          const int column = std::min(width - 1, int((px + rng.next()) * float(width) / kProbesPerAxis));
          const int row = std::min(height - 1, int((py + rng.next()) * float(height) / kProbesPerAxis));
          const ViewSample& v = view[std::size_t(row) * std::size_t(width) + std::size_t(column)];
          if (v.hit)
            probes.push_back({v.surface.position, v.surface.shading_normal, v.surface.albedo, v.cluster,
                              topology::cell_hits(topo.occluders, topo.grid.shape, v.surface.position)});
        }
      prepare_vpls(lights, scene_lights, settings, mix(uint64_t(seed) ^ mix(uint64_t(s))), probes, graph);
    }
    const WorldStrategies world_strategies{scene_lights, settings.world_lights, &sky_guide_};
    {
      StageScope scope(timer, Stage::TopologyDirect);
      parallel_for(pixels, 0, 256, [&](std::size_t i) {
        const ViewSample& v = view[i];
        if (!v.hit) return;
        Rng rng(seed, kDirectLight, (uint64_t(s) << 40) ^ i);
        const Progression progression{mix(uint64_t(seed) ^ mix(kDirectLight)) ^ i, uint32_t(s)};
        direct[i] = v.surface.albedo / kPi *
                    direct_irradiance(lights, v.surface.position, v.surface.shading_normal, direct_rays, rng,
                                      &world_strategies, &progression);
      });
    }
    // Clustered shading (Sec. V.B): view samples grouped by screen tile, exponential depth slice and visibility
    // cluster; each group gets a bounding sphere and, in light assignment (Sec. V.C), its list of VPLs.
    std::vector<uint32_t> group_of(pixels, kNoNode);
    std::vector<GroupLights> assigned;
    const bool clusters_and_gates = settings.topology_visibility == 0;
    if (clusters_and_gates && !vpls_.empty()) {
      StageScope scope(timer, Stage::TopologyAssign);
      float near_depth = std::numeric_limits<float>::infinity(), far_depth = 0.0f;
      for (const ViewSample& v : view)
        if (v.hit && v.depth > 0.0f)
          near_depth = std::min(near_depth, v.depth), far_depth = std::max(far_depth, v.depth);
      const float log_range = std::log(std::max(far_depth / std::max(near_depth, 1e-30f), 1.0f + 1e-6f));
      std::unordered_map<uint64_t, uint32_t> group_index;
      std::vector<glm::vec3> lo, hi;
      std::vector<uint32_t> group_cluster;
      const int size = settings.topology_cluster_size;
      for (std::size_t i = 0; i < pixels; ++i) {
        const ViewSample& v = view[i];
        if (!v.hit) continue;
        const uint64_t tx = uint64_t(int(i % std::size_t(width)) / size),
                       ty = uint64_t(int(i / std::size_t(width)) / size);
        const int slice = v.depth > 0.0f ? std::clamp(int(kDepthSlices * std::log(v.depth / near_depth) / log_range), 0,
                                                      kDepthSlices - 1)
                                         : 0;
        const uint64_t key = mix(mix(mix(tx) ^ ty) ^ uint64_t(slice)) ^ (uint64_t(v.cluster) << 1);
        auto [entry, added] = group_index.try_emplace(key, uint32_t(lo.size()));
        if (added) {
          lo.push_back(v.surface.position);
          hi.push_back(v.surface.position);
          group_cluster.push_back(v.cluster);
        }
        group_of[i] = entry->second;
        lo[entry->second] = glm::min(lo[entry->second], v.surface.position);
        hi[entry->second] = glm::max(hi[entry->second], v.surface.position);
      }
      assigned.resize(lo.size());
      const std::vector<EmitterSphere> spheres = emitter_spheres(emitters);
      parallel_for(lo.size(), 0, 4, [&](std::size_t g) {
        const glm::vec3 centre = 0.5f * (lo[g] + hi[g]);
        const float sphere = 0.5f * glm::length(hi[g] - lo[g]) + offset;
        const uint32_t cluster = group_cluster[g];
        GroupLights& group = assigned[g];
        for (uint32_t subset = 0; subset < interleaving.subsets; ++subset) {
          for (std::size_t l = subset; l < vpls_.size(); l += interleaving.subsets) {
            // A VPL lights its normal's half-space only: one with the whole group behind it lights none of it.
            if (glm::dot(vpls_[l].normal, centre - vpls_[l].position) <= -sphere) continue;
            const Test test = visibility_test(settings.topology_visibility, topo, vpl_cluster_[l], cluster);
            // Rays only for the VPLs whose light reached a probe past the clusters and gates: a solid wall costs
            // no rays at shading.
            if (test == Test::kShadowRay && cluster != kNoNode && !vpl_lit_by_ray_[l]) continue;
            const bool emitter = near_emitter(spheres, vpls_[l].position, centre, sphere);
            if (test != Test::kGates) {
              group.lights.push_back({uint32_t(l), test, 0, 0, emitter});
              continue;
            }
            // The first gate of a walk must open toward the group.
            const auto first = uint32_t(group.gates.size());
            for (uint32_t gate : graph.gates_of[vpl_cluster_[l]])
              if (sphere_meets_gate_cone(vpls_[l].position, topo.gates[gate], centre, sphere))
                group.gates.push_back(gate);
            if (group.gates.size() > first)
              group.lights.push_back({uint32_t(l), test, first, uint32_t(group.gates.size()) - first, emitter});
          }
          group.subset_end.push_back(uint32_t(group.lights.size()));
        }
      });
    }
    {
      StageScope scope(timer, Stage::TopologyIndirect);
      parallel_for(std::size_t(height), 0, 1, [&](std::size_t row) {
        std::vector<RuledPair> ruled;  // a pixel's lights the rule gave a verdict, for its checks
        for (std::size_t i = row * std::size_t(width); i < (row + 1) * std::size_t(width); ++i) {
          const ViewSample& v = view[i];
          gathered[i] = {};
          near[i] = {};
          if (!v.hit) continue;
          const uint32_t subset = interleaving.subset(x0 + int(i % std::size_t(width)), y0 + int(row));
          const glm::vec3 x = v.surface.position, n = v.surface.shading_normal;
          glm::vec3 irradiance(0.0f), second_irradiance(0.0f);  // all bounces; the second alone
          const auto add = [&](const Vpl& vpl, glm::vec3 e) {
            irradiance += e;
            if (vpl.bounce == 2) second_irradiance += e;
          };
          const auto blocked = [&](const Vpl& vpl) {
            return !scene_.clear_between(x + v.surface.normal * offset, vpl.position + vpl.normal * offset);
          };
          if (clusters_and_gates) {
            if (group_of[i] == kNoNode) continue;
            const GroupLights& group = assigned[group_of[i]];
            const auto occluder_hits = topology::cell_hits(topo.occluders, topo.grid.shape, x);
            const auto voxel = float(topo.grid.shape.voxel_size);
            // The rule's share of a light at x, and whether a shadow ray gave it (then it is exact).
            struct Verdict {
              float share;
              bool by_ray;
            };
            const auto verdict = [&](uint32_t l, Test test, std::span<const uint32_t> first_gates,
                                     bool near_emitter) -> Verdict {
              const Vpl& vpl = vpls_[l];
              float entry = 0.0f;
              const Reach reach = test == Test::kGates ? reaches(topo, graph, vpl_cluster_[l], vpl.position, v.cluster,
                                                                 x, entry, first_gates)
                                                       : Reach::kYes;
              if (reach == Reach::kNo) return {0.0f, false};
              if (test == Test::kShadowRay || reach == Reach::kIfRayClear) return {blocked(vpl) ? 0.0f : 1.0f, true};
              if (near_emitter && emitter_hides(emitters, test, reach, vpl.position, x, emitter_margin))
                return {0.0f, false};
              return {occluder_share(test, reach, entry, occluder_hits, vpl.position - x, voxel), false};
            };
            // Ray checks: every check_every-th light of the subset, from a random start, has the rule's verdict
            // checked by a shadow ray, and the difference taken check_every times: a control variate that makes
            // the estimate the shadow rays' in expectation. The rule is right for most pairs, so few checks add
            // little noise. A light the assignment left out has the verdict 0 (no gate opens toward the group, or
            // its light reached no probe by a ray): a gate the rule missed shows there.
            const std::size_t stride = std::size_t(interleaving.subsets) * std::size_t(std::max(check_every, 1));
            std::size_t first_check = vpls_.size();  // none
            if (check_every > 0) {
              Rng rng(seed, kRayChecks, (uint64_t(s) << 40) ^ i);
              first_check = subset + interleaving.subsets * std::size_t(rng.next() * float(check_every));
            }
            const auto check = [&](const Vpl& vpl, glm::vec3 e, float rule, float weight) {
              const float seen = blocked(vpl) ? 0.0f : 1.0f;
              if (seen != rule) add(vpl, weight * (seen - rule) * e);
            };
            const std::span<const Assignment> subset_lights = group.of_subset(subset);
            ruled.clear();
            float rule_light = 0.0f;
            for (const Assignment& a : subset_lights) {
              const Vpl& vpl = vpls_[a.vpl];
              const glm::vec3 e = vpl_irradiance(vpl, x, n, clamp);
              // The visibility tests last: most VPLs face away from a given sample.
              if (!(e.r + e.g + e.b > 0.0f)) continue;
              const Verdict rule =
                  verdict(a.vpl, a.test, std::span(group.gates).subspan(a.first_gate, a.first_gates), a.near_emitter);
              if (rule.share > 0.0f) add(vpl, rule.share * e);
              rule_light += rule.share * (e.r + e.g + e.b);
              if (!rule.by_ray) ruled.push_back({a.vpl, e, rule.share});
            }
            // A light whose correction, taken check_every times, would outweigh all the light the rule gives the
            // pixel is checked every sample, once: Sponza's gallery had one VPL the rule kept out 1.2 m from a
            // pixel, and its 16-fold correction alone was 15 times the pixel's converged light. Which lights are
            // checked so depends on the rule's verdicts alone, not on the checks, so the expectation stays the
            // shadow rays'.
            std::size_t next_check = first_check;
            for (const RuledPair& pair : ruled) {
              while (next_check < pair.vpl) next_check += stride;
              const float light = pair.irradiance.r + pair.irradiance.g + pair.irradiance.b;
              if (float(check_every) * light >= rule_light)
                check(vpls_[pair.vpl], pair.irradiance, pair.share, 1.0f);
              else if (next_check == pair.vpl)
                check(vpls_[pair.vpl], pair.irradiance, pair.share, float(check_every));
            }
            auto assigned_light = subset_lights.begin();
            for (std::size_t l = first_check; l < vpls_.size(); l += stride) {
              while (assigned_light != subset_lights.end() && assigned_light->vpl < l) ++assigned_light;
              if (assigned_light != subset_lights.end() && assigned_light->vpl == l) continue;  // checked above
              const glm::vec3 e = vpl_irradiance(vpls_[l], x, n, clamp);
              if (e.r + e.g + e.b > 0.0f) check(vpls_[l], e, 0.0f, float(check_every));
            }
          } else {
            const bool shadow_rays = settings.topology_visibility == 1;
            for (std::size_t l = subset; l < vpls_.size(); l += interleaving.subsets) {
              const Vpl& vpl = vpls_[l];
              const glm::vec3 e = vpl_irradiance(vpl, x, n, clamp);
              if (!(e.r + e.g + e.b > 0.0f)) continue;
              if (shadow_rays && blocked(vpl)) continue;
              add(vpl, e);
            }
          }
          gathered[i] = {float(interleaving.subsets) * irradiance, float(interleaving.subsets) * second_irradiance};
          if (clamp > 0.0f) {
            Rng rng(seed, kNearField, (uint64_t(s) << 40) ^ i);
            const Progression progression{mix(uint64_t(seed) ^ mix(kNearField)) ^ i, uint32_t(s)};
            near[i] = near_field(scene_, v.surface, lights, direct_rays, world_strategies, clamp, progression, rng);
          }
        }
      });
      parallel_for(std::size_t(height), 0, 1, [&](std::size_t row) {
        for (std::size_t i = row * std::size_t(width); i < (row + 1) * std::size_t(width); ++i)
          recombined[i] = view[i].hit ? interleaving.recombine(view, gathered, width, height, x0, y0, i) : Gathered{};
      });
      // A pixel's first-bounce irradiance: the VPLs' and its near field's.
      const auto first_bounce = [&](std::size_t i) {
        return recombined[i].all - recombined[i].second + near[i].irradiance;
      };
      const UnseenFirstBounce unseen(two_bounces && clamp > 0.0f ? std::span<const Vpl>(vpls_) : std::span<const Vpl>{},
                                     clamp);
      // The first-bounce irradiance at y, the surface a pixel's near-field ray met.
      const auto first_bounce_at = [&](std::size_t i, const NearField& y) -> glm::vec3 {
        std::optional<glm::dvec2> point =
            image_point(world_to_clip, glm::dvec3(y.position), camera.width, camera.height);
        if (point) *point -= glm::dvec2(x0, y0) + glm::dvec2(jitter);
        const auto seen = [&](std::size_t j) {
          return view[j].hit ? std::optional<SeenSurface>({view[j].surface.position, view[j].surface.shading_normal})
                             : std::nullopt;
        };
        if (const std::optional<std::size_t> j = first_bounce_pixel(y, i, point, width, height, clamp, seen))
          return first_bounce(*j);
        Rng rng(seed, kUnseenNearField, (uint64_t(s) << 40) ^ i);
        const Progression progression{mix(uint64_t(seed) ^ mix(kUnseenNearField)) ^ i, uint32_t(s)};
        return unseen.at(scene_, y, lights, direct_rays, world_strategies, progression, rng);
      };
      parallel_for(std::size_t(height), 0, 1, [&](std::size_t row) {
        for (std::size_t i = row * std::size_t(width); i < (row + 1) * std::size_t(width); ++i) {
          const ViewSample& v = view[i];
          if (!v.hit) {
            indirect[i] = second[i] = glm::vec3(0.0f);
            continue;
          }
          const Gathered& g = recombined[i];
          const NearField& y = near[i];
          const glm::vec3 near_second =
              two_bounces && y.normal != glm::vec3(0.0f) ? y.reflectance * first_bounce_at(i, y) : glm::vec3(0.0f);
          indirect[i] = v.surface.albedo / kPi * (g.all + y.irradiance + near_second);
          second[i] = v.surface.albedo / kPi * (g.second + near_second);
        }
      });
    }
    sky_guide_.update();
    for (std::size_t i = 0; i < pixels; ++i) {
      const ViewSample& v = view[i];
      if (!v.hit) {  // the world, as the GPU methods' compose pass adds it
        sums.combined[i] += background_seen * world_radiance(v.direction);
        sums.alpha[i] += background_alpha;
        continue;
      }
      sums.alpha[i] += 1.0f;
      sums.direct[i] += direct[i];
      sums.indirect[i] += indirect[i];
      sums.second[i] += second[i];
      sums.emission[i] += v.surface.emission;
      sums.albedo[i] += v.surface.albedo;
      sums.normal[i] += v.surface.shading_normal;
      sums.combined[i] += direct[i] + indirect[i] + v.surface.emission;
      sums.depth[i] = std::min(sums.depth[i], v.depth);
    }
    // With every toggle off the pass stays transparent and costs nothing (the viewport without its overlay).
    const bool debug_pass =
        settings.topology_show_clusters || settings.topology_show_skeleton || settings.topology_show_gates;
    if (s == 0 && debug_pass) {
      StageScope scope(timer, Stage::TopologyDebug);
      draw_topology_pass(topo, settings, camera, x0, y0, width, height, view, topology_image);
    }
    callbacks.progress(s + 1, 0.5f + 0.5f * float(s + 1) / float(settings.samples));
    if (!schedule.another_fits(s + 1)) {
      samples_done = s + 1;
      break;
    }
    if (s + 1 < settings.samples && schedule.publish_due(s + 1)) {
      std::shared_ptr<Frame> partial = make_frame(s + 1);
      const bool noise_reached = schedule.published(*partial, s + 1);
      // The frame that meets Noise Target is the render's last: it is not made a second time.
      if (noise_reached) schedule.fill_noise(*partial, s + 1);
      callbacks.publish(std::move(partial));
      if (noise_reached) return true;
    }
  }
  std::shared_ptr<Frame> frame = make_frame(samples_done);
  schedule.fill_noise(*frame, samples_done);
  callbacks.publish(std::move(frame));
  return true;
}

}  // namespace bounce::cpu
