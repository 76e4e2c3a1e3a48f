// A thin C++ layer over Embree, so CPU code compiles against Embree 3 (Debian 12) or Embree 4 (Debian 13 and
// later) alike and never includes Embree's headers itself. Used by the CPU reference renderers (tests only).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace bounce::embree {

// One Embree device (its thread pool and allocator). Scenes share it; it lives as long as any of them.
class Device {
 public:
  Device();
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  // "3.13.5", "4.3.0": the Embree library this was built against.
  static const char* version();

 private:
  friend class Scene;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct Hit {
  float t = 0.0f;
  uint32_t geometry_id = 0;  // as returned by Scene::add_triangles
  uint32_t prim_id = 0;      // triangle index within that geometry
  float u = 0.0f, v = 0.0f;  // barycentrics: point = (1 - u - v) p0 + u p1 + v p2
  // Unit geometric normal normalize(cross(p1 - p0, p2 - p0)) (counter-clockwise front face; Embree's own Ng
  // has the opposite orientation), whichever side the ray came from: triangles are two-sided. Where float32
  // flattens the triangle (a zero cross product), -dir.
  glm::vec3 normal{0.0f};
};

// Triangle meshes in world space, copied in, then committed into a BVH. Queries are thread-safe after commit().
class Scene {
 public:
  explicit Scene(std::shared_ptr<Device> device = nullptr);  // nullptr: a device of its own
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;

  // Returns the geometry id. Indices must be < positions.size(); degenerate triangles are kept (Embree never
  // reports hits on them). Only before commit().
  uint32_t add_triangles(std::span<const glm::vec3> positions, std::span<const std::array<uint32_t, 3>> triangles);
  // A triangle soup: vertices 3i, 3i + 1, 3i + 2 make triangle i.
  uint32_t add_triangles(std::span<const glm::vec3> soup);
  // Builds the BVH (robust mode: watertight, no missed hits on shared edges). Throws std::runtime_error on an
  // Embree error.
  void commit();
  bool committed() const;

  // The closest hit with t in [tmin, tmax]; dir need not be unit (t is in units of |dir|). A ray Embree cannot
  // take (a non-finite or overflowing origin or direction, tmin < 0 or > tmax: its debug builds assert on them)
  // hits nothing.
  std::optional<Hit> intersect(glm::vec3 origin, glm::vec3 dir, float tmin, float tmax) const;
  // Whether any hit has t in [tmin, tmax]. A ray Embree cannot take is not occluded.
  bool occluded(glm::vec3 origin, glm::vec3 dir, float tmin, float tmax) const;
  // The same, counting only the hits `counts` accepts (alpha cut-outs let the others through): the closest hits
  // are walked in order. `counts` may be empty: every hit counts.
  using HitFilter = std::function<bool(const Hit&)>;
  std::optional<Hit> intersect(glm::vec3 origin, glm::vec3 dir, float tmin, float tmax, const HitFilter& counts) const;
  bool occluded(glm::vec3 origin, glm::vec3 dir, float tmin, float tmax, const HitFilter& counts) const;

  std::array<glm::vec3, 3> triangle(uint32_t geometry_id, uint32_t prim_id) const;
  uint32_t geometry_count() const;
  uint32_t triangle_count(uint32_t geometry_id) const;
  // Axis-aligned bounds of every vertex added; min > max while empty.
  glm::vec3 bounds_min() const;
  glm::vec3 bounds_max() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bounce::embree
