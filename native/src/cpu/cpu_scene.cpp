#include "cpu/cpu_scene.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <map>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec4.hpp>

#include "cpu/random.h"
#include "error.h"

namespace bounce::cpu {

namespace {

std::shared_ptr<embree::Device> start_embree() {
  try {
    return std::make_shared<embree::Device>();
  } catch (const std::exception& e) {
    fail(BOUNCE_ERROR_RAY_TRACING,
         std::string("Embree could not start (") + e.what() +
             "): ray-traced shadows, the Topology method, FLC's Indirect Shadows and Auto need it; Direct, FLC and "
             "SSVP render without it with Shadows > Shadow Method: Shadow Maps");
  }
}

}  // namespace

bool CpuScene::sync(const GpuScene& scene) {
  if (!device_) {
    device_ = start_embree();
    bvh_ = std::make_unique<embree::Scene>(device_);
  }
  if (scene.geometry_version() == version_) return false;
  version_ = scene.geometry_version();
  positions_.clear();
  normals_.clear();
  uvs_.clear();
  material_of_.clear();
  materials_.clear();
  std::map<const BounceMaterial*, uint32_t> material_index;
  for (const GpuScene::DrawnPart& part : scene.drawn_parts()) {
    auto [entry, added] = material_index.try_emplace(&part.material, uint32_t(materials_.size()));
    if (added) {
      const BounceMaterial& m = part.material;
      const TextureData* texture = scene.texture_data(m.base_color_texture);
      materials_.push_back({glm::make_vec3(m.base_color), glm::make_vec3(m.emission), texture,
                            scene.texture_data(m.emission_texture), m.alpha, m.alpha_threshold,
                            texture && m.alpha_from_texture != 0});
    }
    const glm::mat4& to_world = part.instance.object_to_world;
    const glm::mat3 normal_to_world(part.instance.normal_to_world);
    for (uint32_t i = 0; i < part.submesh.vertex_count; ++i) {
      const Vertex& vertex = part.mesh.vertices[part.submesh.first_vertex + i];
      positions_.push_back(glm::vec3(to_world * glm::vec4(glm::make_vec3(vertex.position), 1.0f)));
      const glm::vec3 n = normal_to_world * glm::make_vec3(vertex.normal);
      const float length = glm::length(n);
      normals_.push_back(length > 0.0f && std::isfinite(length) ? n / length : glm::vec3(0.0f));
      uvs_.push_back({vertex.uv[0], vertex.uv[1]});
    }
    material_of_.insert(material_of_.end(), part.submesh.vertex_count / 3, entry->second);
  }
  hash_ = mix(positions_.size());
  for (const glm::vec3& p : positions_)
    for (int c = 0; c < 3; ++c) hash_ = mix(hash_ ^ std::bit_cast<uint32_t>(p[c]));
  bvh_ = std::make_unique<embree::Scene>(device_);
  bvh_->add_triangles(positions_);
  bvh_->commit();
  const bool cutouts = std::any_of(materials_.begin(), materials_.end(), [](const Material& m) {
    return m.alpha_from_texture || m.alpha < m.alpha_threshold;
  });
  opaque_ = cutouts ? embree::Scene::HitFilter([this](const embree::Hit& hit) { return has_surface(hit); })
                    : embree::Scene::HitFilter();
  return true;
}

std::optional<embree::Hit> CpuScene::intersect(glm::vec3 origin, glm::vec3 dir, float tmin, float tmax) const {
  return bvh_->intersect(origin, dir, tmin, tmax, opaque_);
}

bool CpuScene::occluded(glm::vec3 origin, glm::vec3 dir, float tmin, float tmax) const {
  return bvh_->occluded(origin, dir, tmin, tmax, opaque_);
}

bool CpuScene::clear_between(glm::vec3 from, glm::vec3 to) const {
  const float distance = glm::length(to - from);
  return !(distance > 0.0f) || !occluded(from, (to - from) / distance, 0.0f, distance);
}

bool CpuScene::has_surface(const embree::Hit& hit) const {
  const Material& material = materials_[material_of_[hit.prim_id]];
  float alpha = material.alpha;
  if (material.alpha_from_texture) alpha *= texture_sample(*material.texture, uv(hit.prim_id, hit.u, hit.v)).a;
  return !(alpha < material.alpha_threshold);
}

float CpuScene::radius() const {
  if (positions_.empty()) return 0.0f;
  return 0.5f * glm::length(bounds_max() - bounds_min());
}

float CpuScene::ray_offset() const {
  if (positions_.empty()) return 1e-30f;
  const glm::vec3 extent = glm::max(glm::abs(bounds_min()), glm::abs(bounds_max()));
  constexpr float kRelative = 1e-5f;  // float32 steps are 1.2e-7 of a coordinate; positions carry a few of them
  return kRelative * std::max({radius(), extent.x, extent.y, extent.z, 1e-30f});
}

glm::vec2 CpuScene::uv(uint32_t triangle, float u, float v) const {
  return (1.0f - u - v) * uvs_[3 * triangle] + u * uvs_[3 * triangle + 1] + v * uvs_[3 * triangle + 2];
}

glm::vec3 CpuScene::albedo(uint32_t triangle, float u, float v) const {
  const Material& material = materials_[material_of_[triangle]];
  if (!material.texture) return material.base_color;
  return material.base_color * glm::vec3(texture_sample(*material.texture, uv(triangle, u, v)));
}

Surface CpuScene::surface(const embree::Hit& hit, glm::vec3 dir) const {
  const uint32_t t = hit.prim_id;
  const float w = 1.0f - hit.u - hit.v;
  Surface s;
  s.position = w * positions_[3 * t] + hit.u * positions_[3 * t + 1] + hit.v * positions_[3 * t + 2];
  s.normal = glm::dot(hit.normal, dir) > 0.0f ? -hit.normal : hit.normal;
  glm::vec3 shading = w * normals_[3 * t] + hit.u * normals_[3 * t + 1] + hit.v * normals_[3 * t + 2];
  const float length = glm::length(shading);
  shading = length > 0.0f && std::isfinite(length) ? shading / length : s.normal;
  s.shading_normal = glm::dot(shading, s.normal) < 0.0f ? -shading : shading;
  s.albedo = albedo(t, hit.u, hit.v);
  const Material& material = materials_[material_of_[t]];
  s.emission = material.emission_texture
                   ? material.emission * glm::vec3(texture_sample(*material.emission_texture, uv(t, hit.u, hit.v)))
                   : material.emission;
  return s;
}

}  // namespace bounce::cpu
