// libFuzzer harness over the C API's scene and settings input (issue 18): each input is a sequence of calls
// (meshes, textures, materials, instances, lights, world, settings) whose counts match the buffers passed, as the
// API's contract asks, and whose contents are arbitrary bytes: indices out of range, NaN, infinities, denormals,
// huge and negative values, unknown enums. Every call must return a status, never crash or trip ASan/UBSan; the
// scene statistics are then read back (the render thread applies the edits, GPU upload included).
//
//   build: CC=clang CXX=clang++ cmake -DBOUNCE_SANITIZE=ON -DBOUNCE_LIBFUZZER=ON ... (scripts/test, stage libfuzzer)
//   run:   bounce_api_fuzz tests/native/fuzz_corpus/api -max_total_time=60
// Rendering is left to the scene fuzzer (bounce_scene_fuzz), which draws valid-looking scenes with every method;
// here one execution must stay well under a millisecond so that millions run.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "bounce/bounce.h"

namespace {

constexpr uint32_t kMaxElements = 64;

// A value made of the next sizeof(T) bytes (zeros once the input runs out).
template <typename T>
T raw_struct(FuzzedDataProvider& data) {
  T value{};
  const std::vector<uint8_t> bytes = data.ConsumeBytes<uint8_t>(sizeof(T));
  if (!bytes.empty()) std::memcpy(&value, bytes.data(), bytes.size());
  return value;
}

template <typename T>
std::vector<T> raw_values(FuzzedDataProvider& data, std::size_t count) {
  std::vector<T> values(count);
  for (T& value : values) value = raw_struct<T>(data);
  return values;
}

void set_mesh(BounceEngine* engine, FuzzedDataProvider& data) {
  const uint64_t key = data.ConsumeIntegralInRange<uint64_t>(0, 3);
  const uint32_t vertices = data.ConsumeIntegralInRange<uint32_t>(0, kMaxElements);
  const uint32_t triangles = data.ConsumeIntegralInRange<uint32_t>(0, kMaxElements);
  const std::vector<float> positions = raw_values<float>(data, 3 * vertices);
  std::vector<uint32_t> indices(3 * triangles);
  for (uint32_t& index : indices)
    index = data.ConsumeBool() ? data.ConsumeIntegral<uint32_t>()
                               : data.ConsumeIntegralInRange<uint32_t>(0, vertices > 0 ? vertices - 1 : 0);
  const std::vector<float> normals = raw_values<float>(data, 9 * triangles);
  const std::vector<float> uvs = raw_values<float>(data, 6 * triangles);
  const std::vector<int32_t> slots = raw_values<int32_t>(data, triangles);
  BounceMeshDesc mesh{};
  mesh.vertex_count = vertices;
  mesh.positions = positions.data();
  mesh.triangle_count = triangles;
  mesh.triangles = indices.data();
  mesh.corner_normals = data.ConsumeBool() ? normals.data() : nullptr;
  mesh.corner_uvs = data.ConsumeBool() ? uvs.data() : nullptr;
  mesh.triangle_slots = data.ConsumeBool() ? slots.data() : nullptr;
  bounce_mesh_set(engine, key, &mesh);
}

void set_texture(BounceEngine* engine, FuzzedDataProvider& data) {
  const uint64_t key = data.ConsumeIntegralInRange<uint64_t>(0, 3);
  int32_t width = data.ConsumeIntegralInRange<int32_t>(1, 8), height = data.ConsumeIntegralInRange<int32_t>(1, 8);
  const int32_t format = data.ConsumeIntegralInRange<int32_t>(-1, 3);
  const std::vector<float> pixels = raw_values<float>(data, 8 * 8 * 4);
  const float* source = pixels.data();
  switch (data.ConsumeIntegralInRange<int>(0, 2)) {  // in range; a size of zero or below; no pixels
    case 1:
      (data.ConsumeBool() ? width : height) = data.ConsumeIntegralInRange<int32_t>(INT32_MIN, 0);
      break;
    case 2:
      source = nullptr;
      break;
    default:
      break;
  }
  bounce_texture_set(engine, key, width, height, format, source);
}

void set_materials(BounceEngine* engine, FuzzedDataProvider& data) {
  const uint32_t count = data.ConsumeIntegralInRange<uint32_t>(0, 8);
  std::vector<BounceMaterial> materials(count);
  for (BounceMaterial& material : materials) material = raw_struct<BounceMaterial>(data);
  bounce_materials_set(engine, count, materials.data());
}

void set_instances(BounceEngine* engine, FuzzedDataProvider& data) {
  const uint32_t count = data.ConsumeIntegralInRange<uint32_t>(0, 8);
  const uint32_t slot_count = data.ConsumeIntegralInRange<uint32_t>(0, 16);
  std::vector<uint64_t> keys(count);
  for (uint64_t& key : keys) key = data.ConsumeIntegralInRange<uint64_t>(0, 4);
  std::vector<float> matrices = raw_values<float>(data, 16 * count);
  if (data.ConsumeBool())  // mostly sane transforms: a scale and a translation
    for (uint32_t i = 0; i < count; ++i) {
      float* m = &matrices[16 * i];
      for (int j = 0; j < 16; ++j)
        if (j % 5 != 0 && j < 12) m[j] = 0.0f;
      m[15] = 1.0f;
    }
  std::vector<uint32_t> offsets(count), counts(count);
  for (uint32_t i = 0; i < count; ++i) {
    offsets[i] = data.ConsumeIntegralInRange<uint32_t>(0, slot_count);
    counts[i] = data.ConsumeIntegralInRange<uint32_t>(0, slot_count - offsets[i]);
  }
  std::vector<uint32_t> slot_materials(slot_count);
  for (uint32_t& material : slot_materials)
    material = data.ConsumeBool() ? data.ConsumeIntegral<uint32_t>() : data.ConsumeIntegralInRange<uint32_t>(0, 8);
  const BounceInstancesDesc desc{count,         keys.data(), matrices.data(),      offsets.data(),
                                 counts.data(), slot_count,  slot_materials.data()};
  bounce_instances_set(engine, &desc);
}

void set_lights(BounceEngine* engine, FuzzedDataProvider& data) {
  const uint32_t count = data.ConsumeIntegralInRange<uint32_t>(0, 8);
  std::vector<BounceLight> lights(count);
  for (BounceLight& light : lights) {
    light = raw_struct<BounceLight>(data);
    if (data.ConsumeBool()) light.type = data.ConsumeIntegralInRange<int32_t>(0, 5);
  }
  bounce_lights_set(engine, count, lights.data());
}

void set_world(BounceEngine* engine, FuzzedDataProvider& data) {
  BounceWorld world = raw_struct<BounceWorld>(data);
  if (data.ConsumeBool()) world.environment_texture = data.ConsumeIntegralInRange<uint64_t>(0, 3);
  bounce_world_set(engine, &world);
}

void validate_settings(FuzzedDataProvider& data) {
  BounceSettings settings{};
  bounce_settings_defaults(&settings);
  if (data.ConsumeBool()) {
    settings = raw_struct<BounceSettings>(data);
  } else {  // defaults with a few bytes overwritten: one setting at a time out of range
    auto* bytes = reinterpret_cast<uint8_t*>(&settings);
    for (int i = data.ConsumeIntegralInRange<int>(0, 4); i > 0; --i)
      bytes[data.ConsumeIntegralInRange<std::size_t>(0, sizeof(settings) - 1)] = data.ConsumeIntegral<uint8_t>();
  }
  bounce_settings_validate(&settings);
}

BounceEngine* shared_engine() {
  static BounceEngine* engine = [] {
    BounceEngine* created = nullptr;
    if (bounce_engine_create(nullptr, &created) != BOUNCE_OK) std::abort();  // the harness itself cannot run
    return created;
  }();
  return engine;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* bytes, std::size_t size) {
  BounceEngine* engine = shared_engine();
  FuzzedDataProvider data(bytes, size);
  for (int call = 0; call < 16 && data.remaining_bytes() > 0; ++call) {
    switch (data.ConsumeIntegralInRange<int>(0, 8)) {
      case 0:
        set_mesh(engine, data);
        break;
      case 1:
        bounce_mesh_remove(engine, data.ConsumeIntegralInRange<uint64_t>(0, 3));
        break;
      case 2:
        set_texture(engine, data);
        break;
      case 3:
        bounce_texture_remove(engine, data.ConsumeIntegralInRange<uint64_t>(0, 3));
        break;
      case 4:
        set_materials(engine, data);
        break;
      case 5:
        set_instances(engine, data);
        break;
      case 6:
        set_lights(engine, data);
        break;
      case 7:
        set_world(engine, data);
        break;
      default:
        validate_settings(data);
        break;
    }
  }
  BounceSceneStats stats{};
  bounce_scene_stats(engine, &stats);
  return 0;
}
