#include "gpu_scene.h"

#include <algorithm>
#include <cstddef>

#include "error.h"

namespace bounce {

namespace {

// std430 mirror of shaders/common/scene.glsl `Material`.
struct GpuMaterial {
  float base_color_alpha[4];
  float emission_threshold[4];
  int32_t flags[4];  // has texture, alpha from texture, -, -
};

struct GpuInstance {
  glm::mat4 object_to_world;
  glm::mat4 normal_to_world;
};

GLenum internal_format(int32_t format) {
  switch (format) {
    case BOUNCE_TEXTURE_RGBA8_SRGB:
      return GL_SRGB8_ALPHA8;
    case BOUNCE_TEXTURE_RGBA8_LINEAR:
      return GL_RGBA8;
    default:
      return GL_RGBA32F;
  }
}

int mip_levels(int width, int height) {
  int levels = 1;
  for (int size = std::max(width, height); size > 1; size /= 2) ++levels;
  return levels;
}

}  // namespace

GpuScene::GpuScene() {
  GLuint id = 0;
  glCreateVertexArrays(1, &id);
  vertex_array_ = gl::VertexArray(id);
  glEnableVertexArrayAttrib(id, 0);
  glEnableVertexArrayAttrib(id, 1);
  glEnableVertexArrayAttrib(id, 2);
  glEnableVertexArrayAttrib(id, 3);
  glVertexArrayAttribFormat(id, 0, 3, GL_FLOAT, GL_FALSE, offsetof(Vertex, position));
  glVertexArrayAttribFormat(id, 1, 3, GL_FLOAT, GL_FALSE, offsetof(Vertex, normal));
  glVertexArrayAttribFormat(id, 2, 2, GL_FLOAT, GL_FALSE, offsetof(Vertex, uv));
  glVertexArrayAttribIFormat(id, 3, 1, GL_UNSIGNED_INT, offsetof(Vertex, random));
  for (GLuint a = 0; a < 4; ++a) glVertexArrayAttribBinding(id, a, 0);
  white_texture_ = gl::make_texture_2d(GL_RGBA8, 1, 1);
  const unsigned char white[4] = {255, 255, 255, 255};
  glTextureSubImage2D(white_texture_.id(), 0, 0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, white);
}

void GpuScene::set_mesh(uint64_t key, std::shared_ptr<const MeshData> mesh) {
  GpuMesh gpu;
  gpu.vertices = gl::make_buffer(mesh->vertices.size() * sizeof(Vertex), mesh->vertices.data(), 0);
  gl::check("uploading a mesh");
  gpu.data = std::move(mesh);
  meshes_[key] = std::move(gpu);
  dirty_ = true;
}

void GpuScene::remove_mesh(uint64_t key) { dirty_ |= meshes_.erase(key) > 0; }

void GpuScene::set_texture(uint64_t key, std::shared_ptr<const TextureData> texture) {
  const TextureData& data = *texture;
  GpuTexture gpu;
  const int levels = mip_levels(data.width, data.height);
  gpu.texture = gl::make_texture_2d(internal_format(data.format), data.width, data.height, levels);
  const GLuint id = gpu.texture.id();
  glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_REPEAT);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  const bool is_float = data.format == BOUNCE_TEXTURE_RGBA32F;
  glTextureSubImage2D(id, 0, 0, 0, data.width, data.height, GL_RGBA, is_float ? GL_FLOAT : GL_UNSIGNED_BYTE,
                      data.bytes.data());
  glGenerateTextureMipmap(id);
  gl::check("uploading a texture");
  gpu.bytes = data.bytes.size() * 4 / 3;
  gpu.data = std::move(texture);
  textures_[key] = std::move(gpu);
  dirty_ = true;
}

void GpuScene::remove_texture(uint64_t key) { dirty_ |= textures_.erase(key) > 0; }

void GpuScene::set_materials(std::vector<BounceMaterial> materials) {
  materials_ = std::move(materials);
  dirty_ = true;
}

void GpuScene::set_instances(std::shared_ptr<const InstanceList> instances) {
  instances_ = std::move(instances);
  drawn_instances_.clear();  // they pointed into the old list; prepare() finds the new ones
  dirty_ = true;
}

void GpuScene::prepare() {
  if (!dirty_) return;
  rebuild();
  dirty_ = false;
  ++geometry_version_;
}

void GpuScene::rebuild() {
  // Material table: the caller's materials, then the default one for unassigned slots.
  std::vector<GpuMaterial> gpu_materials;
  auto add_material = [&](const BounceMaterial& m) {
    const bool has_texture = m.base_color_texture != BOUNCE_NO_TEXTURE && textures_.count(m.base_color_texture);
    gpu_materials.push_back({{m.base_color[0], m.base_color[1], m.base_color[2], m.alpha},
                             {m.emission[0], m.emission[1], m.emission[2], m.alpha_threshold},
                             {has_texture ? 1 : 0, has_texture && m.alpha_from_texture ? 1 : 0, 0, 0}});
  };
  for (const BounceMaterial& m : materials_) add_material(m);
  add_material(default_material_);  // index materials_.size(), see material_of
  gl::upload_buffer(material_buffer_, material_capacity_, gpu_materials.size() * sizeof(GpuMaterial),
                    gpu_materials.data());

  // Group instances by (mesh, submesh, material) so each group is one instanced draw.
  std::vector<GpuInstance> gpu_instances;
  std::map<std::tuple<const GpuMesh*, std::size_t, uint32_t>, std::vector<uint32_t>> groups;
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  drawn_triangles_ = 0;
  drawn_instances_.clear();
  out_of_range_instances_ = 0;
  if (instances_) {
    for (const InstanceData& instance : instances_->instances) {
      const auto mesh = meshes_.find(instance.mesh_key);
      if (mesh == meshes_.end() || mesh->second.data->empty()) continue;
      const MeshData& data = *mesh->second.data;
      glm::vec3 instance_lo(INFINITY), instance_hi(-INFINITY);
      for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 local((corner & 1) ? data.bounds_max.x : data.bounds_min.x,
                              (corner & 2) ? data.bounds_max.y : data.bounds_min.y,
                              (corner & 4) ? data.bounds_max.z : data.bounds_min.z);
        const glm::vec3 world = glm::vec3(instance.object_to_world * glm::vec4(local, 1.0f));
        instance_lo = glm::min(instance_lo, world);
        instance_hi = glm::max(instance_hi, world);
      }
      if (!within_range(instance_lo) || !within_range(instance_hi)) {  // the range policy: scene_data.cpp
        ++out_of_range_instances_;
        continue;
      }
      lo = glm::min(lo, instance_lo);
      hi = glm::max(hi, instance_hi);
      drawn_instances_.push_back(&instance);
      const auto index = static_cast<uint32_t>(gpu_instances.size());
      gpu_instances.push_back({instance.object_to_world, instance.normal_to_world});
      for (std::size_t s = 0; s < data.submeshes.size(); ++s) {
        groups[{&mesh->second, s, material_of(instance, data.submeshes[s])}].push_back(index);
        drawn_triangles_ += data.submeshes[s].vertex_count / 3;
      }
    }
  }
  bounds_min_ = gpu_instances.empty() ? glm::vec3(0.0f) : lo;
  bounds_max_ = gpu_instances.empty() ? glm::vec3(0.0f) : hi;

  std::vector<uint32_t> instance_lists;
  batches_.clear();
  for (const auto& [key, members] : groups) {
    const auto& [mesh, submesh, material] = key;
    const SubMesh& range = mesh->data->submeshes[submesh];
    batches_.push_back({mesh, range.first_vertex, range.vertex_count, material,
                        static_cast<uint32_t>(instance_lists.size()), static_cast<uint32_t>(members.size())});
    instance_lists.insert(instance_lists.end(), members.begin(), members.end());
  }
  gl::upload_buffer(instance_buffer_, instance_capacity_, gpu_instances.size() * sizeof(GpuInstance),
                    gpu_instances.data());
  gl::upload_buffer(instance_list_buffer_, instance_list_capacity_, instance_lists.size() * sizeof(uint32_t),
                    instance_lists.data());
  gl::check("uploading the instance and material tables");
}

void GpuScene::draw(GLenum mode) const {
  glBindVertexArray(vertex_array_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kInstances, instance_buffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kInstanceLists, instance_list_buffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kMaterials, material_buffer_.id());
  const GpuMesh* bound_mesh = nullptr;
  for (const Batch& batch : batches_) {
    if (batch.mesh != bound_mesh) {
      glVertexArrayVertexBuffer(vertex_array_.id(), 0, batch.mesh->vertices.id(), 0, sizeof(Vertex));
      bound_mesh = batch.mesh;
    }
    const BounceMaterial* material = batch.material < materials_.size() ? &materials_[batch.material] : nullptr;
    auto texture_or_white = [&](uint64_t key) {
      const GLuint id = texture_id(key);
      return id != 0 ? id : white_texture_.id();
    };
    glBindTextureUnit(binding::kBaseColorUnit, texture_or_white(material ? material->base_color_texture : 0));
    glBindTextureUnit(binding::kEmissionUnit, texture_or_white(material ? material->emission_texture : 0));
    glUniform1i(binding::kInstanceOffset, static_cast<GLint>(batch.instance_offset));
    glUniform1i(binding::kMaterial, static_cast<GLint>(batch.material));
    glDrawArraysInstanced(mode, static_cast<GLint>(batch.first_vertex), static_cast<GLsizei>(batch.vertex_count),
                          static_cast<GLsizei>(batch.instance_count));
  }
  glBindVertexArray(0);
}

BounceSceneStats GpuScene::stats() const {
  BounceSceneStats s{};
  s.mesh_count = static_cast<uint32_t>(meshes_.size());
  s.instance_count = instances_ ? static_cast<uint32_t>(instances_->instances.size()) : 0;
  s.triangle_count = drawn_triangles_;
  for (const auto& [key, mesh] : meshes_) {
    s.dropped_triangles += mesh.data->dropped_triangles;
    s.out_of_range_triangles += mesh.data->out_of_range_triangles;
    s.gpu_bytes += mesh.data->vertices.size() * sizeof(Vertex);
  }
  for (const auto& [key, texture] : textures_) s.gpu_bytes += texture.bytes;
  s.light_count = static_cast<uint32_t>(lights_.lights.size());
  s.skipped_lights = lights_.skipped;
  s.out_of_range_instances = out_of_range_instances_;
  s.out_of_range_lights = lights_.out_of_range;
  s.clamped_lights = lights_.clamped;
  s.texture_count = static_cast<uint32_t>(textures_.size());
  for (int a = 0; a < 3; ++a) {
    s.bounds_min[a] = bounds_min_[a];
    s.bounds_max[a] = bounds_max_[a];
  }
  return s;
}

uint32_t GpuScene::material_of(const InstanceData& instance, const SubMesh& submesh) const {
  const auto slot = static_cast<std::size_t>(submesh.slot);
  const uint32_t material = slot < instance.slot_materials.size() ? instance.slot_materials[slot] : UINT32_MAX;
  return std::min(material, static_cast<uint32_t>(materials_.size()));
}

std::vector<GpuScene::DrawnPart> GpuScene::drawn_parts() const {
  std::vector<DrawnPart> parts;
  for (const InstanceData* instance : drawn_instances_) {
    const MeshData& mesh = *meshes_.at(instance->mesh_key).data;
    for (const SubMesh& submesh : mesh.submeshes) {
      const uint32_t material = material_of(*instance, submesh);
      parts.push_back(
          {mesh, *instance, submesh, material < materials_.size() ? materials_[material] : default_material_});
    }
  }
  return parts;
}

GLuint GpuScene::texture_id(uint64_t key) const {
  const auto texture = textures_.find(key);
  return texture == textures_.end() ? 0 : texture->second.texture.id();
}

const TextureData* GpuScene::texture_data(uint64_t key) const {
  const auto texture = textures_.find(key);
  return texture == textures_.end() ? nullptr : texture->second.data.get();
}

}  // namespace bounce
