// The scene as the CPU renderer sees it: every drawn triangle in world space, with its shading normals, UVs and
// material, and an Embree BVH over them. Built from the GpuScene's CPU-side data on the render thread.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "embree/embree_device.h"
#include "gpu_scene.h"

namespace bounce::cpu {

struct Surface {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f};          // unit geometric normal, turned toward the incoming ray
  glm::vec3 shading_normal{0.0f};  // unit interpolated normal, on the same side
  glm::vec3 albedo{0.0f};          // base colour times the texture
  glm::vec3 emission{0.0f};
};

class CpuScene {
 public:
  CpuScene() = default;
  CpuScene(const CpuScene&) = delete;  // opaque() refers to this object
  CpuScene& operator=(const CpuScene&) = delete;
  // Rebuilds from `scene` (prepared) when its geometry changed since the last call; returns whether it did.
  // The first call starts Embree (BOUNCE_ERROR_RAY_TRACING when it cannot): only the CPU paths need it.
  bool sync(const GpuScene& scene);

  const embree::Scene& bvh() const { return *bvh_; }  // after sync()
  // Rays as the rasterizer sees the scene: a hit where an alpha cut-out has no surface (alpha below its
  // threshold, as shaders/common/scene.glsl decides) lets the ray through. The topology itself is built from
  // every triangle (soup()).
  std::optional<embree::Hit> intersect(glm::vec3 origin, glm::vec3 dir, float tmin, float tmax) const;
  bool occluded(glm::vec3 origin, glm::vec3 dir, float tmin, float tmax) const;
  // Whether nothing lies on the segment from `from` to `to`, to its very end: the callers lift both ends off their
  // surfaces. (Stopping a lift short of the end let a VPL in the corner of a sealed block light the room through
  // the block's other face.)
  bool clear_between(glm::vec3 from, glm::vec3 to) const;
  const embree::Scene::HitFilter& opaque() const { return opaque_; }  // empty without cut-outs
  std::span<const glm::vec3> soup() const { return positions_; }      // three corners per triangle
  std::size_t triangle_count() const { return positions_.size() / 3; }
  // Of every corner position: the key of the topology cache.
  uint64_t geometry_hash() const { return hash_; }
  glm::vec3 bounds_min() const { return bvh_ ? bvh_->bounds_min() : glm::vec3(0.0f); }
  glm::vec3 bounds_max() const { return bvh_ ? bvh_->bounds_max() : glm::vec3(0.0f); }
  float radius() const;  // half the bounding box diagonal; 0 when empty
  // How far off a surface a ray leaving it starts: clear of the float32 rounding of a position (1e-5 of the
  // scene's largest coordinate or radius), and no further. The lift moves shadow edges by the offset over the
  // tangent of the light's elevation: at 2e-4 of the radius (6 mm in Sponza) it lifted points on a wall over the
  // arch above them into all of a grazing sun's disk, where Cycles sees 7.5 % of it.
  float ray_offset() const;

  // The surface at a hit of a ray with direction `dir`.
  Surface surface(const embree::Hit& hit, glm::vec3 dir) const;

 private:
  struct Material {
    glm::vec3 base_color{0.8f};
    glm::vec3 emission{0.0f};
    const TextureData* texture = nullptr;  // owned by the GpuScene, which outlives every sync
    const TextureData* emission_texture = nullptr;
    float alpha = 1.0f, alpha_threshold = 0.0f;
    bool alpha_from_texture = false;
  };
  glm::vec2 uv(uint32_t triangle, float u, float v) const;
  glm::vec3 albedo(uint32_t triangle, float u, float v) const;
  bool has_surface(const embree::Hit& hit) const;

  uint64_t version_ = 0;
  std::vector<glm::vec3> positions_, normals_;
  std::vector<glm::vec2> uvs_;
  std::vector<uint32_t> material_of_;  // per triangle
  std::vector<Material> materials_;
  uint64_t hash_ = 0;
  std::shared_ptr<embree::Device> device_;
  std::unique_ptr<embree::Scene> bvh_;
  embree::Scene::HitFilter opaque_;
};

}  // namespace bounce::cpu
