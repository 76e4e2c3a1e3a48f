// The scene as the core holds it on the CPU: validated, ready to upload. Preparation runs on the caller's
// thread (bounce_mesh_set etc.) so the render thread only uploads; none of this touches GL and all of it is
// unit-tested without a context.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bounce/bounce.h"

namespace bounce {

// ---- Numeric range policy (scene_data.cpp explains it) --------------------------------------------------------

// How far from the world origin (metres, per axis) Bounce takes coordinates: vertices, instance bounds, light
// positions and sizes.
constexpr float kMaxCoordinate = 1e9f;
// The largest light intensity (W/sr, W/m^2 or W/m^2/sr per channel) Bounce takes; brighter lights are dimmed to it.
constexpr float kMaxIntensity = 1e15f;

// Whether every coordinate of p is within kMaxCoordinate (false for NaN).
bool within_range(glm::vec3 p);

// Dims an intensity brighter than kMaxIntensity to it, keeping its hue; negative and NaN channels become 0, and
// where a channel overflowed, every positive one takes the limit.
void dim_to_max_intensity(float (&intensity)[3]);

struct Vertex {
  float position[3];
  float normal[3];
  float uv[2];
  // Forward Light Cuts' v_rand (paper Sec. 6): uniform, fixed per original vertex index, so a triangle's
  // random stays the same while the mesh keeps its topology, whatever its positions do.
  uint32_t random;
};

struct SubMesh {  // triangles of one material slot, contiguous in the vertex array
  int32_t slot;
  uint32_t first_vertex;
  uint32_t vertex_count;
};

struct MeshData {
  std::vector<Vertex> vertices;  // three per triangle, sorted by slot
  std::vector<SubMesh> submeshes;
  uint64_t dropped_triangles = 0;       // non-finite or zero-area
  uint64_t out_of_range_triangles = 0;  // a corner beyond kMaxCoordinate
  glm::vec3 bounds_min{0.0f}, bounds_max{0.0f};
  bool empty() const { return vertices.empty(); }
};

// Validates indices (throws Error naming the triangle at fault) and drops what cannot be drawn.
std::shared_ptr<const MeshData> prepare_mesh(uint64_t key, const BounceMeshDesc& desc);

struct InstanceData {
  uint64_t mesh_key;
  glm::mat4 object_to_world;
  glm::mat4 normal_to_world;  // inverse transpose
  std::vector<uint32_t> slot_materials;
};

struct InstanceList {
  std::vector<InstanceData> instances;
  uint32_t dropped = 0;  // non-finite or singular transforms
};

// Material indices are checked when drawing: one out of range uses the default material.
std::shared_ptr<const InstanceList> prepare_instances(const BounceInstancesDesc& desc);

struct LightList {
  std::vector<BounceLight> lights;     // finite, with some positive intensity
  std::vector<uint32_t> source_index;  // each one's index in the list the caller gave
  uint32_t skipped = 0;                // zero or non-finite intensity
  uint32_t out_of_range = 0;           // a point, spot or area light placed beyond kMaxCoordinate
  uint32_t clamped = 0;                // dimmed to kMaxIntensity, or sized down to kMaxCoordinate
};

LightList prepare_lights(uint32_t count, const BounceLight* lights);

// A BOUNCE_LIGHT_AREA_TRIANGLE's corners in world space, and its area (one side).
std::array<glm::vec3, 3> triangle_light_corners(const BounceLight& light);
float triangle_light_area(const BounceLight& light);
// An area light's emitting area: its surface, both sides of a triangle counted.
float emitting_area(const BounceLight& light);

// A triangle light from world-space corners, with radiance `radiance` on both sides; its frame is orthonormal
// (x along the first edge, z the normal), as the shadow cube maps need.
BounceLight make_triangle_light(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 radiance);

std::vector<BounceMaterial> prepare_materials(uint32_t count, const BounceMaterial* materials);

struct TextureData {
  int32_t width = 0, height = 0;
  int32_t format = BOUNCE_TEXTURE_RGBA8_SRGB;
  std::vector<unsigned char> bytes;
};

std::shared_ptr<const TextureData> prepare_texture(uint64_t key, int32_t width, int32_t height, int32_t format,
                                                   const void* pixels);

// Texel (x, y) in linear colour, wrapping like GL_REPEAT; and the bilinear lookup at uv, rows bottom first, like
// the GPU's GL_LINEAR at level 0.
glm::vec4 texture_texel(const TextureData& texture, int x, int y);
glm::vec4 texture_sample(const TextureData& texture, glm::vec2 uv);

// The material every slot without one uses: grey 0.8, like Blender's default surface.
BounceMaterial default_material();

}  // namespace bounce
