// Builds small scenes through the C API and renders them on the default EGL platform (llvmpipe here).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "bounce/bounce.h"
#include "topology_scenes.h"

namespace bounce::test {

constexpr float kPi = 3.14159265358979f;

#define ASSERT_BOUNCE_OK(call) ASSERT_EQ((call), BOUNCE_OK) << bounce_last_error()

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<float> values;
  const float* at(int x, int y) const { return values.data() + (std::size_t(y) * width + x) * channels; }
};

inline BounceLight make_light(int type, glm::vec3 position, glm::vec3 intensity) {
  BounceLight light{};
  light.type = type;
  light.cast_shadow = 1;
  std::memcpy(light.position, &position[0], 12);
  const float x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, z[3] = {0, 0, 1};
  std::memcpy(light.axis_x, x, 12);
  std::memcpy(light.axis_y, y, 12);
  std::memcpy(light.axis_z, z, 12);  // shining down (-z)
  std::memcpy(light.intensity, &intensity[0], 12);
  light.spot_half_angle = kPi / 4;
  return light;
}

// A UV sphere of radius r around the origin.
inline void sphere_mesh(float r, int segments, int rings, std::vector<float>& positions,
                        std::vector<uint32_t>& triangles) {
  for (int j = 0; j <= rings; ++j) {
    const float theta = kPi * j / rings;
    for (int i = 0; i <= segments; ++i) {
      const float phi = 2.0f * kPi * i / segments;
      positions.insert(positions.end(),
                       {r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi), r * std::cos(theta)});
    }
  }
  const auto at = [&](int i, int j) { return static_cast<uint32_t>(j * (segments + 1) + i); };
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < segments; ++i) {
      if (j > 0) triangles.insert(triangles.end(), {at(i, j), at(i, j + 1), at(i + 1, j)});
      if (j < rings - 1) triangles.insert(triangles.end(), {at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)});
    }
}

class RenderFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_BOUNCE_OK(bounce_engine_create(nullptr, &engine_));
    bounce_settings_defaults(&settings_);
    settings_.samples = 1;
    settings_.filter_width = 0.0f;
  }
  void TearDown() override { bounce_engine_destroy(engine_); }

  // A square of side `size` in the z = 0 plane, centred at the origin, facing +z.
  void add_mesh(uint64_t key, const std::vector<float>& positions, const std::vector<uint32_t>& triangles,
                const std::vector<float>& corner_uvs = {}) {
    BounceMeshDesc mesh{};
    mesh.vertex_count = static_cast<uint32_t>(positions.size() / 3);
    mesh.positions = positions.data();
    mesh.triangle_count = static_cast<uint32_t>(triangles.size() / 3);
    mesh.triangles = triangles.data();
    mesh.corner_uvs = corner_uvs.empty() ? nullptr : corner_uvs.data();
    ASSERT_BOUNCE_OK(bounce_mesh_set(engine_, key, &mesh));
  }
  // A triangle soup (vertices 3i, 3i + 1, 3i + 2 make triangle i) as one mesh, with a uv per corner if given.
  void add_soup(uint64_t key, const std::vector<glm::vec3>& vertices, const std::vector<glm::vec2>& uvs = {}) {
    std::vector<float> positions, corner_uvs;
    std::vector<uint32_t> triangles;
    for (const glm::vec3& v : vertices) {
      triangles.push_back(static_cast<uint32_t>(positions.size() / 3));
      positions.insert(positions.end(), {v.x, v.y, v.z});
    }
    for (const glm::vec2& uv : uvs) corner_uvs.insert(corner_uvs.end(), {uv.x, uv.y});
    add_mesh(key, positions, triangles, corner_uvs);
  }
  void add_plane(uint64_t key, float size) {
    const float h = size / 2;
    add_mesh(key, {-h, -h, 0, h, -h, 0, h, h, 0, -h, h, 0}, {0, 1, 2, 0, 2, 3});
  }
  // One instance per (key, transform), all with material 0.
  void set_instances(const std::vector<uint64_t>& keys, const std::vector<glm::mat4>& transforms) {
    std::vector<float> matrices;
    for (const glm::mat4& m : transforms) matrices.insert(matrices.end(), glm::value_ptr(m), glm::value_ptr(m) + 16);
    std::vector<uint32_t> offsets(keys.size(), 0), counts(keys.size(), 1), slots = {0};
    BounceInstancesDesc desc{static_cast<uint32_t>(keys.size()),
                             keys.data(),
                             matrices.data(),
                             offsets.data(),
                             counts.data(),
                             1,
                             slots.data()};
    ASSERT_BOUNCE_OK(bounce_instances_set(engine_, &desc));
  }
  // One instance per key at the identity, instance i with a grey material of albedo albedos[i].
  void set_grey_instances(const std::vector<uint64_t>& keys, const std::vector<float>& albedos) {
    std::vector<glm::vec3> colours;
    for (const float albedo : albedos) colours.emplace_back(albedo);
    set_coloured_instances(keys, colours);
  }
  // One instance per key at the identity, instance i with a material of base colour colours[i].
  void set_coloured_instances(const std::vector<uint64_t>& keys, const std::vector<glm::vec3>& colours) {
    std::vector<BounceMaterial> materials(colours.size());
    for (std::size_t i = 0; i < colours.size(); ++i) {
      for (int c = 0; c < 3; ++c) materials[i].base_color[c] = colours[i][c];
      materials[i].alpha = 1.0f;
      materials[i].alpha_threshold = 0.5f;
    }
    ASSERT_BOUNCE_OK(bounce_materials_set(engine_, static_cast<uint32_t>(materials.size()), materials.data()));
    std::vector<float> matrices;
    for (std::size_t i = 0; i < keys.size(); ++i) {
      const glm::mat4 identity(1.0f);
      matrices.insert(matrices.end(), glm::value_ptr(identity), glm::value_ptr(identity) + 16);
    }
    std::vector<uint32_t> offsets(keys.size()), counts(keys.size(), 1), slots(keys.size());
    for (std::size_t i = 0; i < keys.size(); ++i) offsets[i] = slots[i] = static_cast<uint32_t>(i);
    const BounceInstancesDesc desc{static_cast<uint32_t>(keys.size()),
                                   keys.data(),
                                   matrices.data(),
                                   offsets.data(),
                                   counts.data(),
                                   uint32_t(slots.size()),
                                   slots.data()};
    ASSERT_BOUNCE_OK(bounce_instances_set(engine_, &desc));
  }
  void set_albedo(float albedo) {
    BounceMaterial material{};
    material.base_color[0] = material.base_color[1] = material.base_color[2] = albedo;
    material.alpha = 1.0f;
    material.alpha_threshold = 0.5f;
    ASSERT_BOUNCE_OK(bounce_materials_set(engine_, 1, &material));
  }
  // A world of `radiance` (times `environment`, if given), unrotated.
  void set_world(glm::vec3 radiance, uint64_t environment = BOUNCE_NO_TEXTURE) {
    BounceWorld world{};
    for (int i = 0; i < 3; ++i) world.background[i] = radiance[i];
    world.environment_texture = environment;
    world.world_to_environment[0] = world.world_to_environment[4] = world.world_to_environment[8] = 1.0f;
    ASSERT_BOUNCE_OK(bounce_world_set(engine_, &world));
  }
  void set_lights(const std::vector<BounceLight>& lights) {
    ASSERT_BOUNCE_OK(bounce_lights_set(engine_, static_cast<uint32_t>(lights.size()), lights.data()));
  }
  // Orthographic camera above the origin looking down -z, covering [-half, half]^2.
  void look_down(float half, int size) {
    const glm::mat4 view = glm::lookAt(glm::vec3(0, 0, 50), glm::vec3(0), glm::vec3(0, 1, 0));
    const glm::mat4 projection = glm::ortho(-half, half, -half, half, 1.0f, 200.0f);
    set_camera(view, projection, size, size);
  }
  // The only light: a sun of 5 W/m^2 in the direction `towards` (from the scene towards the sun).
  void set_sun(glm::vec3 towards) {
    BounceLight sun = make_light(BOUNCE_LIGHT_SUN, {0, 0, 10}, glm::vec3(5.0f));
    towards = glm::normalize(towards);
    const glm::vec3 x = glm::normalize(glm::cross(glm::vec3(0, 1, 0), towards)), y = glm::cross(towards, x);
    std::memcpy(sun.axis_z, &towards[0], 12);
    std::memcpy(sun.axis_x, &x[0], 12);
    std::memcpy(sun.axis_y, &y[0], 12);
    set_lights({sun});
  }
  void set_camera(const glm::mat4& view, const glm::mat4& projection, int width, int height) {
    camera_ = BounceCamera{};
    std::memcpy(camera_.world_to_view, glm::value_ptr(view), 64);
    std::memcpy(camera_.projection, glm::value_ptr(projection), 64);
    camera_.width = width;
    camera_.height = height;
  }
  // The open box (topology_scenes.h, albedo 0.8; `box`: its walls with other things inside) lit by a point light
  // under its ceiling, seen through its open side.
  void build_lit_open_box(const Soup& box = open_box()) {
    add_soup(1, box.vertices);
    set_instances({1}, {glm::mat4(1.0f)});
    set_albedo(0.8f);
    set_lights({make_light(BOUNCE_LIGHT_POINT, glm::vec3(0.0f, 1.0f, 1.9f), glm::vec3(20.0f))});
    set_camera(glm::lookAt(glm::vec3(0.0f, -3.5f, 1.0f), glm::vec3(0.0f, 1.0f, 1.0f), glm::vec3(0, 0, 1)),
               glm::perspective(glm::radians(38.0f), 1.0f, 0.05f, 100.0f), 48, 48);
  }
  // The furnace of the issues: a closed diffuse sphere (R = 2, albedo 0.8) with a 1000 W point light at its
  // centre, seen from the centre. First-bounce irradiance on the wall: rho Phi / (4 pi R^2); second: rho times it.
  void build_furnace() {
    std::vector<float> positions;
    std::vector<uint32_t> triangles;
    sphere_mesh(2.0f, 96, 48, positions, triangles);
    add_mesh(1, positions, triangles);
    set_instances({1}, {glm::mat4(1.0f)});
    set_albedo(0.8f);
    set_lights({make_light(BOUNCE_LIGHT_POINT, glm::vec3(0.0f), glm::vec3(1000.0f / (4.0f * kPi)))});
    const glm::mat4 view = glm::lookAt(glm::vec3(0.0f), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0));
    set_camera(view, glm::perspective(glm::radians(60.0f), 1.0f, 0.05f, 10.0f), 48, 48);
    settings_.filter_width = 0.0f;
  }
  static double mean_channel(const Image& image, int channel) {
    double sum = 0.0;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) sum += image.at(x, y)[channel];
    return sum / (image.width * image.height);
  }
  static double mean_red(const Image& image) { return mean_channel(image, 0); }

  // Renders and returns one AOV; fails the test on any render error.
  Image render(int aov = BOUNCE_AOV_COMBINED) {
    EXPECT_EQ(bounce_render_start(engine_, &settings_, &camera_), BOUNCE_OK) << bounce_last_error();
    EXPECT_EQ(bounce_render_wait(engine_, -1), BOUNCE_OK) << bounce_last_error();
    return read(aov);
  }
  Image read(int aov) {
    BounceFrameInfo info{};
    EXPECT_EQ(bounce_frame_info(engine_, &info), BOUNCE_OK) << bounce_last_error();
    Image image;
    image.width = info.width;
    image.height = info.height;
    image.channels = bounce_aov_channels(aov);
    image.values.resize(std::size_t(info.width) * info.height * image.channels);
    EXPECT_EQ(bounce_frame_read(engine_, aov, image.values.data(), image.values.size()), BOUNCE_OK)
        << bounce_last_error();
    return image;
  }

  BounceEngine* engine_ = nullptr;
  BounceSettings settings_{};
  BounceCamera camera_{};
};

// World position of a pixel centre for look_down(half, size) on the z = 0 plane.
inline glm::vec3 pixel_world(int x, int y, float half, int size) {
  return {-half + (x + 0.5f) * 2 * half / size, -half + (y + 0.5f) * 2 * half / size, 0.0f};
}

inline bool all_finite(const Image& image) {
  for (float v : image.values)
    if (!std::isfinite(v)) return false;
  return true;
}

}  // namespace bounce::test
