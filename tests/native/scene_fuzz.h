// The native scene fuzzer: random scenes through the C API, with the hard inputs the numeric range policy
// guards against (NaN, huge and tiny coordinates and powers, degenerate triangles, transforms and cameras) and
// every setting drawn from its range in settings.def. Case `index` of seed `seed` is always the same scene: the
// generator's only source of randomness is a counter-based hash of (seed, index, draw), so a failing case is
// reproduced by its two numbers alone (the repro files of tests/native/fuzz_repros/ hold just those).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "render_fixture.h"

namespace bounce::test::fuzz {

// SplitMix64 and its own mappings to floats and integers: the standard distributions' output differs between
// standard libraries, and a seed must replay the same scenes wherever the tests are built.
class Random {
 public:
  Random(uint64_t seed, uint64_t index) : state_(seed * 0x9E3779B97F4A7C15ull ^ (index + 0x632BE59BD9B4E019ull)) {
    next();
  }
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  float uniform() { return static_cast<float>(next() >> 40) * 0x1.0p-24f; }  // [0, 1)
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
  int integer(int lo, int hi) { return lo + static_cast<int>(next() % (static_cast<uint64_t>(hi) - lo + 1)); }
  bool chance(float p) { return uniform() < p; }
  template <typename T, std::size_t N>
  T pick(const std::array<T, N>& values) {
    return values[next() % N];
  }

 private:
  uint64_t state_;
};

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kFloatMax = std::numeric_limits<float>::max();

// One coordinate: mostly a scene-sized value, sometimes one of the inputs the range policy is about.
inline float hard_coordinate(Random& random, float extent) {
  if (!random.chance(0.03f)) return random.uniform(-extent, extent);
  const float sign = random.chance(0.5f) ? 1.0f : -1.0f;
  return sign * random.pick(std::array{kNaN, kInf, kFloatMax, 1e30f, 1e10f, 1e9f, 1e-30f, 1e-40f, 0.0f});
}

// Half the lights shine normally, so that the renderers' paths past the light checks run too.
inline float light_power(Random& random) {
  const float normal = random.uniform(1.0f, 1000.0f);
  return random.chance(0.5f) ? normal : random.pick(std::array{0.0f, -100.0f, 1e-20f, normal, 1e30f, kFloatMax, kNaN});
}

struct Mesh {
  uint64_t key = 0;
  std::vector<float> positions;
  std::vector<uint32_t> triangles;
  std::vector<float> corner_normals;  // empty: flat normals
  std::vector<float> corner_uvs;
  std::vector<int32_t> triangle_slots;
};

struct Scene {
  std::vector<Mesh> meshes;
  std::vector<BounceMaterial> materials;
  std::vector<uint64_t> instance_keys;
  std::vector<float> instance_matrices;
  std::vector<uint32_t> slot_offsets, slot_counts, slot_materials;
  std::vector<BounceLight> lights;
  BounceWorld world{};
  int environment_width = 0, environment_height = 0;  // world.environment_texture's RGBA32F texels, if any
  std::vector<float> environment;
  BounceCamera camera{};
  BounceSettings settings{};
};

// Random triangles over random vertices (some shared, some repeated, rarely an index out of range), or a closed
// sphere or a floor, so that most scenes have surfaces a light can reach.
inline Mesh random_mesh(Random& random, uint64_t key) {
  Mesh mesh;
  mesh.key = key;
  const float shape = random.uniform();
  if (shape < 0.2f) {  // a floor to catch the light
    const float h = random.uniform(2.0f, 10.0f);
    mesh.positions = {-h, -h, 0, h, -h, 0, h, h, 0, -h, h, 0};
    mesh.triangles = {0, 1, 2, 0, 2, 3};
  } else if (shape < 0.5f) {
    const float radius = random.uniform(0.2f, 3.0f);
    const int segments = random.integer(3, 12), rings = random.integer(2, 8);
    sphere_mesh(radius, segments, rings, mesh.positions, mesh.triangles);
  } else {
    const int vertex_count = random.integer(3, 24);
    const float extent = random.pick(std::array{3.0f, 3.0f, 1e-3f, 1e4f});
    for (int i = 0; i < 3 * vertex_count; ++i) mesh.positions.push_back(hard_coordinate(random, extent));
    const int triangle_count = random.integer(1, 24);
    for (int i = 0; i < 3 * triangle_count; ++i)
      mesh.triangles.push_back(static_cast<uint32_t>(random.integer(0, vertex_count - 1)));
    if (random.chance(0.03f)) mesh.triangles[random.next() % mesh.triangles.size()] = vertex_count;  // an error
  }
  const std::size_t triangle_count = mesh.triangles.size() / 3;
  if (random.chance(0.3f))
    for (std::size_t i = 0; i < 9 * triangle_count; ++i) mesh.corner_normals.push_back(hard_coordinate(random, 1.0f));
  if (random.chance(0.2f))
    for (std::size_t i = 0; i < 6 * triangle_count; ++i) mesh.corner_uvs.push_back(hard_coordinate(random, 2.0f));
  if (random.chance(0.3f))
    for (std::size_t i = 0; i < triangle_count; ++i) mesh.triangle_slots.push_back(random.integer(-1, 4));
  return mesh;
}

inline glm::vec3 random_direction(Random& random) {
  const float z = random.uniform(-1.0f, 1.0f), phi = random.uniform(0.0f, 2.0f * kPi);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Object to world: mostly a rotation, scale and translation; sometimes flat, mirrored, huge or NaN.
inline glm::mat4 random_transform(Random& random) {
  glm::mat4 m = glm::translate(
      glm::mat4(1.0f), {hard_coordinate(random, 4.0f), hard_coordinate(random, 4.0f), hard_coordinate(random, 4.0f)});
  const float angle = random.uniform(0.0f, 2.0f * kPi);
  m = glm::rotate(m, angle, random_direction(random));
  const float scale =
      random.chance(0.85f) ? random.uniform(0.3f, 2.0f) : random.pick(std::array{0.0f, -1.0f, 1e-20f, 1e20f, kNaN});
  return glm::scale(m, {scale, random.chance(0.9f) ? scale : 0.0f, scale});
}

inline BounceLight random_light(Random& random) {
  const int type = random.integer(BOUNCE_LIGHT_POINT, BOUNCE_LIGHT_AREA_ELLIPSE);
  const float far = random.pick(std::array{1e5f, 1e9f, 1e10f, 1e30f, kFloatMax});
  const glm::vec3 position = random.chance(0.9f) ? glm::vec3{random.uniform(-4.0f, 4.0f), random.uniform(-4.0f, 4.0f),
                                                             random.uniform(-1.0f, 6.0f)}
                                                 : far * random_direction(random);
  const float power = light_power(random);
  const glm::vec3 tint{random.uniform(), random.uniform(), random.uniform()};
  BounceLight light = make_light(type, position, random.chance(0.8f) ? glm::vec3(power) : power * tint);
  light.cast_shadow = random.chance(0.7f);
  if (random.chance(0.7f)) {  // a frame turned toward the scene; else straight down, as make_light leaves it
    const glm::vec3 z = -random_direction(random),
                    helper = std::abs(z.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::vec3 x = glm::normalize(glm::cross(helper, z)), y = glm::cross(z, x);
    std::memcpy(light.axis_x, &x[0], 12);
    std::memcpy(light.axis_y, &y[0], 12);
    std::memcpy(light.axis_z, &z[0], 12);
  }
  if (random.chance(0.03f)) light.axis_z[random.integer(0, 2)] = random.pick(std::array{0.0f, kNaN, 1e30f});
  const auto size = [&] {
    return random.chance(0.96f) ? random.uniform(0.0f, 1.0f)
                                : random.pick(std::array{1e-30f, 1e20f, kFloatMax, -1.0f, kNaN});
  };
  light.radius = size();
  light.half_size[0] = size();
  light.half_size[1] = size();
  light.spot_half_angle =
      random.chance(0.96f) ? random.uniform(0.0f, kPi / 2) : random.pick(std::array{0.0f, kPi, -1.0f, kNaN});
  light.spot_blend = random.chance(0.96f) ? random.uniform() : random.pick(std::array{-1.0f, 2.0f, kNaN});
  light.spot_cos_falloff = random.chance(0.5f);
  light.sun_angle = random.chance(0.96f) ? random.uniform(0.0f, kPi / 4) : random.pick(std::array{kPi, -1.0f, kNaN});
  return light;
}

// A camera looking from around the scene toward it; sometimes a degenerate one (eye on the target, zero or
// inverted clip range, zero field of view, a NaN matrix), a bad size or a crop.
inline BounceCamera random_camera(Random& random) {
  const glm::vec3 target{random.uniform(-1.0f, 1.0f), random.uniform(-1.0f, 1.0f), random.uniform(-1.0f, 1.0f)};
  const float distance = random.chance(0.03f) ? 0.0f : random.uniform(2.0f, 15.0f);  // 0: the eye on the target
  const glm::vec3 eye = target + distance * random_direction(random);
  const glm::mat4 view = glm::lookAt(eye, target, random.chance(0.95f) ? glm::vec3(0, 0, 1) : eye - target);
  const float near = random.chance(0.96f) ? random.uniform(0.01f, 1.0f) : random.pick(std::array{0.0f, -1.0f, 1e-30f});
  const float far = random.chance(0.96f) ? random.uniform(20.0f, 100.0f) : random.pick(std::array{near, 1e-3f, 1e30f});
  glm::mat4 projection;
  if (random.chance(0.7f)) {
    const float fov = random.chance(0.96f) ? random.uniform(0.2f, 2.5f) : random.pick(std::array{0.0f, 1e-6f, kPi});
    projection = glm::perspective(fov, random.uniform(0.5f, 2.0f), near, far);
  } else {
    const float half =
        random.chance(0.96f) ? random.uniform(0.5f, 10.0f) : random.pick(std::array{0.0f, 1e-30f, 1e30f});
    projection = glm::ortho(-half, half, -half, half, near - 50.0f, far);
  }
  if (random.chance(0.02f)) {
    const int column = random.integer(0, 3);
    projection[column][random.integer(0, 3)] = kNaN;
  }
  BounceCamera camera{};
  std::memcpy(camera.world_to_view, glm::value_ptr(view), 64);
  std::memcpy(camera.projection, glm::value_ptr(projection), 64);
  camera.width = random.chance(0.98f) ? random.integer(1, 48) : random.integer(-2, 0);
  camera.height = random.chance(0.98f) ? random.integer(1, 48) : random.pick(std::array{0, -1, 100000});
  if (random.chance(0.1f)) {
    camera.crop[0] = random.integer(-2, camera.width);
    camera.crop[1] = random.integer(-2, camera.height);
    camera.crop[2] = random.integer(camera.crop[0] - 1, camera.width + 2);
    camera.crop[3] = random.integer(camera.crop[1] - 1, camera.height + 2);
  }
  camera.frame = random.integer(-5, 250);
  return camera;
}

// The defaults, then a third of the settings drawn from their full range (settings.def), then the costly ones
// held small so that a case takes a fraction of a second on llvmpipe.
inline BounceSettings random_settings(Random& random) {
  BounceSettings settings;
  bounce_settings_defaults(&settings);
#define BOUNCE_SETTING(ctype, glsl_type, kind, name, label, def, min, max, smin, smax, flags, group, items, desc) \
  if (random.chance(0.3f)) {                                                                                      \
    if constexpr (std::is_floating_point_v<ctype>)                                                                \
      settings.name = random.chance(0.1f) ? ctype(random.chance(0.5f) ? min : max) : random.uniform(min, max);    \
    else                                                                                                          \
      settings.name = random.integer(min, max);                                                                   \
  }
#include "bounce/settings.def"
#undef BOUNCE_SETTING
  constexpr std::pair<int32_t BounceSettings::*, int32_t> kCostCaps[] = {
      {&BounceSettings::samples, 2},
      {&BounceSettings::bounces, 3},
      {&BounceSettings::shadow_map_size, 256},
      {&BounceSettings::flc_vpls_per_pixel, 4},
      {&BounceSettings::flc_levels, 4},
      {&BounceSettings::ssvp_vpls, 256},
      {&BounceSettings::ssvp_second_vpls, 256},
      {&BounceSettings::ssvp_bouncing_lights, 8},
      {&BounceSettings::ssvp_clusters, 8},
      {&BounceSettings::ssvp_rsm_size, 128},
      {&BounceSettings::ssvp_paraboloid_size, 64},
      {&BounceSettings::topology_resolution, 48},
      {&BounceSettings::topology_vpls, 256},
      {&BounceSettings::world_lights, 8},
      {&BounceSettings::emission_lights, 16},
  };
  for (const auto& [setting, cap] : kCostCaps) settings.*setting = std::min(settings.*setting, cap);
  if (random.chance(0.02f)) settings.samples = random.pick(std::array{0, -1});  // out of range: an error
  return settings;
}

inline Scene generate(uint64_t seed, uint64_t index) {
  Random random(seed, index);
  Scene scene;
  const int mesh_count = random.integer(1, 3);
  for (int i = 0; i < mesh_count; ++i) scene.meshes.push_back(random_mesh(random, 100 + i));
  const int material_count = random.integer(1, 4);
  for (int i = 0; i < material_count; ++i) {
    BounceMaterial material{};
    for (int c = 0; c < 3; ++c) {
      material.base_color[c] = random.chance(0.95f) ? random.uniform() : random.pick(std::array{-1.0f, 1e30f, kNaN});
      material.emission[c] = random.chance(0.8f) ? 0.0f : random.pick(std::array{0.5f, 10.0f, 1e30f, kNaN});
    }
    material.alpha = random.chance(0.9f) ? 1.0f : random.uniform();
    material.alpha_threshold = 0.5f;
    material.double_sided = 1;
    scene.materials.push_back(material);
  }
  const int instance_count = random.integer(1, 6);
  for (int i = 0; i < instance_count; ++i) {
    scene.instance_keys.push_back(100 + random.integer(0, mesh_count - 1));
    const glm::mat4 transform = random.chance(0.2f) ? glm::mat4(1.0f) : random_transform(random);
    scene.instance_matrices.insert(scene.instance_matrices.end(), glm::value_ptr(transform),
                                   glm::value_ptr(transform) + 16);
    scene.slot_offsets.push_back(static_cast<uint32_t>(scene.slot_materials.size()));
    scene.slot_counts.push_back(static_cast<uint32_t>(random.integer(0, 3)));
    for (uint32_t s = 0; s < scene.slot_counts.back(); ++s)
      scene.slot_materials.push_back(static_cast<uint32_t>(random.integer(0, material_count - 1)));
  }
  const int light_count = random.integer(0, 4);
  for (int i = 0; i < light_count; ++i) scene.lights.push_back(random_light(random));
  for (float& channel : scene.world.background)
    channel = random.chance(0.7f) ? 0.0f : random.pick(std::array{0.05f, 1.0f, 1e30f, kNaN});
  scene.world.transparent = random.chance(0.3f);
  scene.camera = random_camera(random);
  scene.settings = random_settings(random);
  scene.settings.method = random.integer(BOUNCE_METHOD_AUTO, BOUNCE_METHOD_TOPOLOGY);
  // Drawn last, so that the scenes of earlier repro files stay as they were.
  scene.world.camera_hidden = random.chance(0.2f);
  if (random.chance(0.4f)) {  // an environment: tiny, wider than the importance table, with a 1e6 sun or worse
    scene.environment_width = random.pick(std::array{1, 2, 64, 700});
    scene.environment_height = random.pick(std::array{1, 32, 300});
    scene.environment.assign(std::size_t(scene.environment_width) * scene.environment_height * 4,
                             random.pick(std::array{0.0f, 0.5f, 1.0f}));
    for (int spot = random.integer(0, 3); spot > 0; --spot)
      scene.environment[random.next() % scene.environment.size()] = random.pick(std::array{1e6f, 1e30f, -1.0f, kNaN});
    scene.world.environment_texture = 77;
    for (int i = 0; i < 9; ++i)  // a rotation, a singular or a NaN Mapping
      scene.world.world_to_environment[i] = random.chance(0.1f) ? random.pick(std::array{0.0f, kNaN, 1e30f})
                                            : i % 4 == 0        ? 1.0f
                                                                : 0.0f;
    if (random.chance(0.4f)) {
      const glm::mat3 rotation =
          glm::mat3(glm::rotate(glm::mat4(1.0f), random.uniform(0.0f, 6.3f), random_direction(random)));
      std::memcpy(scene.world.world_to_environment, glm::value_ptr(rotation), sizeof rotation);
    }
  }
  return scene;
}

// What went wrong in one case; empty when it passed.
struct Outcome {
  std::vector<std::string> failures;
  bool rendered = false;  // else the engine refused the scene, camera or settings, with a message
  std::string refusal;    // that message
};

// Every call must return OK or an error that says why (bounce_last_error non-empty).
inline bool call_ok(BounceStatus status, const char* what, Outcome& outcome) {
  if (status == BOUNCE_OK) return true;
  if (outcome.refusal.empty()) outcome.refusal = std::string(what) + ": " + bounce_last_error();
  if (std::string(bounce_last_error()).empty())
    outcome.failures.push_back(std::string(what) + " failed with status " + std::to_string(status) +
                               " and an empty bounce_last_error()");
  return false;
}

// The silent black frame check, where it can be decided without a reference renderer: shadows, a light's
// orientation, range and falloff make a black Direct pass legitimate for most lights, but an unshadowed sun of
// positive finite power adds intensity * albedo / pi * cos to every surface whose normal faces it, whatever the
// geometry. When some pixel shows such a surface (Albedo and Normal passes) in a channel the sun has, Direct may
// not be all zero. (Powers beyond the range are dimmed, not zeroed, and counted: still positive.)
inline bool sun_must_light(const std::vector<BounceLight>& lights, const Image& albedo, const Image& normal) {
  for (const BounceLight& light : lights) {
    // The engine skips a light with any non-finite field (scene_data.cpp, prepare_lights).
    const float fields[] = {light.position[0], light.position[1],  light.position[2],  light.axis_x[0],
                            light.axis_x[1],   light.axis_x[2],    light.axis_y[0],    light.axis_y[1],
                            light.axis_y[2],   light.axis_z[0],    light.axis_z[1],    light.axis_z[2],
                            light.radius,      light.half_size[0], light.half_size[1], light.spot_half_angle,
                            light.spot_blend,  light.sun_angle,    light.intensity[0], light.intensity[1],
                            light.intensity[2]};
    const glm::vec3 axis = glm::make_vec3(light.axis_z), intensity = glm::make_vec3(light.intensity);
    if (light.type != BOUNCE_LIGHT_SUN || light.cast_shadow ||
        !std::ranges::all_of(fields, [](float v) { return std::isfinite(v); }) || !(glm::length(axis) > 1e-3f) ||
        !glm::all(glm::greaterThan(intensity, glm::vec3(0.0f))))
      continue;
    for (int y = 0; y < albedo.height; ++y)
      for (int x = 0; x < albedo.width; ++x)
        if (std::max({albedo.at(x, y)[0], albedo.at(x, y)[1], albedo.at(x, y)[2]}) > 0.01f &&
            glm::dot(glm::make_vec3(normal.at(x, y)), glm::normalize(axis)) > 0.1f)
          return true;
  }
  return false;
}

// Builds the scene on a fresh engine (so no state of an earlier case, such as SSVP's temporal seeding, reaches
// this one), renders it and checks what the engine gives back: errors with messages, finite AOVs, a frame whose
// non-finite pixel count is zero, and no silent black frame (sun_must_light). Scene edits that fail are allowed
// (their message is checked); the render goes on with what the engine accepted.
inline Outcome run_case(const Scene& scene) {
  Outcome outcome;
  BounceEngine* engine = nullptr;
  if (!call_ok(bounce_engine_create(nullptr, &engine), "bounce_engine_create", outcome)) {
    outcome.failures.push_back(std::string("no engine: ") + bounce_last_error());
    return outcome;
  }
  for (const Mesh& mesh : scene.meshes) {
    BounceMeshDesc desc{};
    desc.vertex_count = static_cast<uint32_t>(mesh.positions.size() / 3);
    desc.positions = mesh.positions.data();
    desc.triangle_count = static_cast<uint32_t>(mesh.triangles.size() / 3);
    desc.triangles = mesh.triangles.data();
    desc.corner_normals = mesh.corner_normals.empty() ? nullptr : mesh.corner_normals.data();
    desc.corner_uvs = mesh.corner_uvs.empty() ? nullptr : mesh.corner_uvs.data();
    desc.triangle_slots = mesh.triangle_slots.empty() ? nullptr : mesh.triangle_slots.data();
    call_ok(bounce_mesh_set(engine, mesh.key, &desc), "bounce_mesh_set", outcome);
  }
  call_ok(bounce_materials_set(engine, static_cast<uint32_t>(scene.materials.size()), scene.materials.data()),
          "bounce_materials_set", outcome);
  const BounceInstancesDesc instances{static_cast<uint32_t>(scene.instance_keys.size()),
                                      scene.instance_keys.data(),
                                      scene.instance_matrices.data(),
                                      scene.slot_offsets.data(),
                                      scene.slot_counts.data(),
                                      static_cast<uint32_t>(scene.slot_materials.size()),
                                      scene.slot_materials.data()};
  call_ok(bounce_instances_set(engine, &instances), "bounce_instances_set", outcome);
  call_ok(bounce_lights_set(engine, static_cast<uint32_t>(scene.lights.size()), scene.lights.data()),
          "bounce_lights_set", outcome);
  if (!scene.environment.empty())
    call_ok(bounce_texture_set(engine, scene.world.environment_texture, scene.environment_width,
                               scene.environment_height, BOUNCE_TEXTURE_RGBA32F, scene.environment.data()),
            "bounce_texture_set", outcome);
  call_ok(bounce_world_set(engine, &scene.world), "bounce_world_set", outcome);
  BounceSceneStats stats{};
  call_ok(bounce_scene_stats(engine, &stats), "bounce_scene_stats", outcome);
  if (call_ok(bounce_render_start(engine, &scene.settings, &scene.camera), "bounce_render_start", outcome) &&
      call_ok(bounce_render_wait(engine, -1), "bounce_render_wait", outcome)) {
    BounceFrameInfo info{};
    if (call_ok(bounce_frame_info(engine, &info), "bounce_frame_info", outcome)) {
      outcome.rendered = true;
      if (info.nonfinite_pixels != 0)
        outcome.failures.push_back("the frame reports " + std::to_string(info.nonfinite_pixels) +
                                   " non-finite pixels (zeroed by the engine)");
      std::array<Image, BOUNCE_AOV_COUNT> aovs;
      for (int aov = 0; aov < BOUNCE_AOV_COUNT; ++aov) {
        Image& image = aovs[aov];
        image.width = info.width;
        image.height = info.height;
        image.channels = bounce_aov_channels(aov);
        image.values.resize(std::size_t(info.width) * info.height * image.channels);
        if (call_ok(bounce_frame_read(engine, aov, image.values.data(), image.values.size()), "bounce_frame_read",
                    outcome) &&
            !all_finite(image))
          outcome.failures.push_back(std::string("NaN or Inf in the ") + bounce_aov_name(aov) + " pass");
      }
      if (sun_must_light(scene.lights, aovs[BOUNCE_AOV_ALBEDO], aovs[BOUNCE_AOV_NORMAL]) &&
          std::ranges::all_of(aovs[BOUNCE_AOV_DIRECT].values, [](float v) { return v == 0.0f; }))
        outcome.failures.push_back("silent black frame: Direct is all zero under an unshadowed sun facing a surface");
    }
  }
  bounce_engine_destroy(engine);
  return outcome;
}

// A repro file: the seed and the case index, which regenerate the scene; the failure as a comment.
struct Repro {
  uint64_t seed = 0, index = 0;
};

inline void write_repro(const std::string& path, const Repro& repro, const std::string& failure) {
  std::ofstream out(path);
  out << "# bounce scene fuzz repro: " << failure << "\nseed " << repro.seed << "\ncase " << repro.index << "\n";
}

inline std::optional<Repro> read_repro(const std::string& path) {
  std::ifstream in(path);
  Repro repro;
  bool has_seed = false, has_case = false;
  for (std::string key; in >> key;) {
    if (key.starts_with("#")) {
      std::getline(in, key);
    } else if (key == "seed") {
      has_seed = static_cast<bool>(in >> repro.seed);
    } else if (key == "case") {
      has_case = static_cast<bool>(in >> repro.index);
    } else {
      return std::nullopt;
    }
  }
  if (!has_seed || !has_case) return std::nullopt;
  return repro;
}

}  // namespace bounce::test::fuzz
