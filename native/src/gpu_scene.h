// The scene on the GPU (render thread only): one vertex buffer per mesh, textures, the instance and material
// tables, and draw batches that draw every instance of a (mesh, slot, material) with one instanced call.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "gl/objects.h"
#include "scene_data.h"

namespace bounce {

// Fixed uniform locations and bindings shared with shaders/common/scene.glsl.
namespace binding {
constexpr GLint kViewProjection = 0;  // mat4 uniform
constexpr GLint kInstanceOffset = 1;  // int uniform
constexpr GLint kMaterial = 2;        // int uniform
constexpr GLuint kSettingsBlock = 0;
constexpr GLuint kInstances = 1;
constexpr GLuint kInstanceLists = 2;
constexpr GLuint kMaterials = 3;
constexpr GLuint kLightBlock = 4;
constexpr GLuint kEmitterOccluders = 12;  // SSBO: this sample's SceneLights::emitter_occluders (renderer.cpp)
constexpr GLuint kBaseColorUnit = 0;
constexpr GLuint kEmissionUnit = 16;
}  // namespace binding

class GpuScene {
 public:
  GpuScene();

  void set_mesh(uint64_t key, std::shared_ptr<const MeshData> mesh);
  void remove_mesh(uint64_t key);
  // The pixels stay on the CPU too, for the topology method's CPU renderer.
  void set_texture(uint64_t key, std::shared_ptr<const TextureData> texture);
  void remove_texture(uint64_t key);
  void set_materials(std::vector<BounceMaterial> materials);
  void set_instances(std::shared_ptr<const InstanceList> instances);
  void set_lights(LightList lights) {
    lights_ = std::move(lights);
    ++light_version_;
  }
  void set_world(const BounceWorld& world) {
    world_ = world;
    ++world_version_;
  }

  // Rebuilds batches and tables if anything changed since the last call.
  void prepare();
  // Draws every batch with the bound program, binding each batch's base-colour texture (cut-outs are
  // discarded by the shaders, per material). GL_PATCHES draws 3-vertex patches for a tessellating program.
  void draw(GLenum mode = GL_TRIANGLES) const;

  // The caller's lamps; a sample lights the scene with SceneLights' list, which starts with them.
  const std::vector<BounceLight>& lamps() const { return lights_.lights; }
  uint32_t lamp_source_index(std::size_t i) const { return lights_.source_index[i]; }
  const BounceWorld& world() const { return world_; }
  // Bumped whenever drawn geometry changes (meshes, instances, cut-out materials): shadow maps depend on it.
  uint64_t geometry_version() const { return geometry_version_; }
  uint64_t light_version() const { return light_version_; }
  uint64_t world_version() const { return world_version_; }
  glm::vec3 bounds_min() const { return bounds_min_; }
  glm::vec3 bounds_max() const { return bounds_max_; }
  // Half the bounding box's diagonal: the length that settings given as a fraction of the scene scale by.
  float radius() const { return 0.5f * glm::length(bounds_max_ - bounds_min_); }
  bool has_geometry() const { return !batches_.empty(); }

  // The drawn geometry for CPU renderers, after prepare(): each drawn instance's submeshes with their materials.
  struct DrawnPart {
    const MeshData& mesh;
    const InstanceData& instance;
    const SubMesh& submesh;
    const BounceMaterial& material;
  };
  std::vector<DrawnPart> drawn_parts() const;
  // The pixels of a texture; nullptr for BOUNCE_NO_TEXTURE or a key not set.
  const TextureData* texture_data(uint64_t key) const;
  // The GL texture of a key; 0 for BOUNCE_NO_TEXTURE or a key not set.
  GLuint texture_id(uint64_t key) const;
  BounceSceneStats stats() const;

 private:
  struct GpuMesh {
    std::shared_ptr<const MeshData> data;
    gl::Buffer vertices;
  };
  struct GpuTexture {
    std::shared_ptr<const TextureData> data;
    gl::Texture texture;
    uint64_t bytes = 0;
  };
  struct Batch {
    const GpuMesh* mesh;
    uint32_t first_vertex, vertex_count;
    uint32_t material;
    uint32_t instance_offset, instance_count;
  };

  void rebuild();
  // The index in materials_ of a submesh's material; materials_.size() (the default material) for an unassigned
  // slot or an index out of range.
  uint32_t material_of(const InstanceData& instance, const SubMesh& submesh) const;

  std::map<uint64_t, GpuMesh> meshes_;
  std::map<uint64_t, GpuTexture> textures_;
  std::vector<BounceMaterial> materials_;
  BounceMaterial default_material_ = default_material();
  std::shared_ptr<const InstanceList> instances_;
  LightList lights_;
  BounceWorld world_{};

  std::vector<Batch> batches_;
  std::vector<const InstanceData*> drawn_instances_;  // in instances_: those with a mesh, within range
  uint32_t out_of_range_instances_ = 0;
  gl::VertexArray vertex_array_;
  gl::Buffer instance_buffer_, instance_list_buffer_, material_buffer_;
  std::size_t instance_capacity_ = 0, instance_list_capacity_ = 0, material_capacity_ = 0;
  gl::Texture white_texture_;
  bool dirty_ = true;
  uint64_t geometry_version_ = 1, light_version_ = 1, world_version_ = 1;
  uint64_t drawn_triangles_ = 0;
  glm::vec3 bounds_min_{0.0f}, bounds_max_{0.0f};
};

}  // namespace bounce
