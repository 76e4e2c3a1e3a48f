// Scene preparation on the CPU: what is dropped, what is refused, and how triangles are grouped.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "error.h"
#include "scene_data.h"

namespace bounce {
namespace {

BounceMeshDesc mesh_of(const std::vector<float>& positions, const std::vector<uint32_t>& triangles) {
  BounceMeshDesc desc{};
  desc.vertex_count = static_cast<uint32_t>(positions.size() / 3);
  desc.positions = positions.data();
  desc.triangle_count = static_cast<uint32_t>(triangles.size() / 3);
  desc.triangles = triangles.data();
  return desc;
}

TEST(PrepareMesh, DropsNonFiniteZeroAreaAndCollinearTriangles) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> positions = {0,   0, 0, 1,   0, 0, 0, 1, 0,  // good
                                        nan, 0, 0, inf, 1, 0,           // non-finite
                                        2,   0, 0, 3,   0, 0};          // collinear with vertex 1
  const std::vector<uint32_t> triangles = {0, 1, 2, 3, 1, 2, 0, 4, 2, 1, 5, 6, 0, 0, 2};
  const auto mesh = prepare_mesh(7, mesh_of(positions, triangles));
  EXPECT_EQ(mesh->vertices.size(), 3u);
  EXPECT_EQ(mesh->dropped_triangles, 4u);
  EXPECT_FLOAT_EQ(mesh->vertices[0].normal[2], 1.0f);
  EXPECT_FLOAT_EQ(mesh->bounds_max[0], 1.0f);
}

TEST(PrepareMesh, RefusesOutOfRangeIndicesNamingTheTriangle) {
  const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::vector<uint32_t> triangles = {0, 1, 2, 0, 1, 9};
  try {
    prepare_mesh(42, mesh_of(positions, triangles));
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BOUNCE_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(e.what()).find("mesh 42: triangle 1 refers to vertex 9 of 3"), std::string::npos);
  }
}

TEST(PrepareMesh, MeshWithoutFacesIsEmptyNotAnError) {
  const std::vector<float> positions = {0, 0, 0, 1, 0, 0};
  const auto mesh = prepare_mesh(1, mesh_of(positions, {}));
  EXPECT_TRUE(mesh->empty());
}

TEST(PrepareMesh, GroupsTrianglesBySlotAndKeepsSplitNormals) {
  const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  const std::vector<uint32_t> triangles = {0, 1, 2, 1, 3, 2, 0, 1, 2};
  const std::vector<int32_t> slots = {2, 0, 2};
  std::vector<float> normals(27, 0.0f);
  for (int c = 0; c < 9; ++c) normals[3 * c + 0] = 2.0f;  // unnormalised +x
  normals[0] = std::numeric_limits<float>::quiet_NaN();   // falls back to the face normal
  BounceMeshDesc desc = mesh_of(positions, triangles);
  desc.triangle_slots = slots.data();
  desc.corner_normals = normals.data();
  const auto mesh = prepare_mesh(1, desc);
  ASSERT_EQ(mesh->submeshes.size(), 2u);
  EXPECT_EQ(mesh->submeshes[0].slot, 0);
  EXPECT_EQ(mesh->submeshes[0].vertex_count, 3u);
  EXPECT_EQ(mesh->submeshes[1].slot, 2);
  EXPECT_EQ(mesh->submeshes[1].vertex_count, 6u);
  // Triangle 0 (slot 2) comes after triangle 1 (slot 0); its first corner had a NaN normal.
  EXPECT_FLOAT_EQ(mesh->vertices[3].normal[2], 1.0f);
  EXPECT_FLOAT_EQ(mesh->vertices[4].normal[0], 1.0f);
}

TEST(PrepareInstances, DropsSingularAndNonFiniteTransforms) {
  const std::vector<uint64_t> keys = {1, 1, 1};
  std::vector<float> matrices(48, 0.0f);
  for (int i = 0; i < 4; ++i) matrices[i * 5] = 1.0f;  // identity
  matrices[16 + 15] = 1.0f;                            // zero scale
  for (int i = 0; i < 4; ++i) matrices[32 + i * 5] = 1.0f;
  matrices[32 + 12] = std::numeric_limits<float>::infinity();  // infinite translation
  const std::vector<uint32_t> offsets = {0, 0, 0}, counts = {1, 1, 1}, slots = {0};
  const BounceInstancesDesc desc{3, keys.data(), matrices.data(), offsets.data(), counts.data(), 1, slots.data()};
  const auto list = prepare_instances(desc);
  EXPECT_EQ(list->instances.size(), 1u);
  EXPECT_EQ(list->dropped, 2u);
}

TEST(PrepareInstances, RefusesSlotRangesBeyondTheTable) {
  const std::vector<uint64_t> keys = {1};
  std::vector<float> matrices(16, 0.0f);
  const std::vector<uint32_t> offsets = {1}, counts = {1}, slots = {0};
  const BounceInstancesDesc desc{1, keys.data(), matrices.data(), offsets.data(), counts.data(), 1, slots.data()};
  EXPECT_THROW(prepare_instances(desc), Error);
}

TEST(PrepareLights, SkipsZeroNegativeNonFiniteAndSizelessAreaLights) {
  BounceLight good{};
  good.type = BOUNCE_LIGHT_POINT;
  good.intensity[0] = 1e9f;
  BounceLight zero = good, nan = good, area = good;
  zero.intensity[0] = 0.0f;
  nan.position[1] = std::numeric_limits<float>::quiet_NaN();
  area.type = BOUNCE_LIGHT_AREA_RECT;  // half size 0
  const BounceLight lights[] = {good, zero, nan, area};
  const LightList list = prepare_lights(4, lights);
  EXPECT_EQ(list.lights.size(), 1u);
  EXPECT_EQ(list.skipped, 3u);
  BounceLight unknown = good;
  unknown.type = 99;
  EXPECT_THROW(prepare_lights(1, &unknown), Error);
}

TEST(PrepareMaterials, ClampsAlbedoAndScrubsNonFinite) {
  BounceMaterial m{};
  m.base_color[0] = 2.0f;
  m.base_color[1] = std::numeric_limits<float>::quiet_NaN();
  m.emission[0] = -1.0f;
  m.alpha = std::numeric_limits<float>::infinity();
  const auto out = prepare_materials(1, &m);
  EXPECT_FLOAT_EQ(out[0].base_color[0], 1.0f);
  EXPECT_FLOAT_EQ(out[0].base_color[1], 0.0f);
  EXPECT_FLOAT_EQ(out[0].emission[0], 0.0f);
  EXPECT_FLOAT_EQ(out[0].alpha, 1.0f);
}

TEST(PrepareTexture, RefusesBadSizesAndScrubsNonFiniteTexels) {
  const float texels[4] = {std::numeric_limits<float>::quiet_NaN(), 1.0f, 0.5f, 1.0f};
  EXPECT_THROW(prepare_texture(1, 0, 1, BOUNCE_TEXTURE_RGBA32F, texels), Error);
  EXPECT_THROW(prepare_texture(BOUNCE_NO_TEXTURE, 1, 1, BOUNCE_TEXTURE_RGBA32F, texels), Error);
  const auto texture = prepare_texture(1, 1, 1, BOUNCE_TEXTURE_RGBA32F, texels);
  EXPECT_FLOAT_EQ(reinterpret_cast<const float*>(texture->bytes.data())[0], 0.0f);
}

}  // namespace
}  // namespace bounce
