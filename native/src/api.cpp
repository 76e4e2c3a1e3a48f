// The C API: argument checks, the catch-all that keeps exceptions inside, and the per-thread last error.
#include <cstring>
#include <new>
#include <string>

#include "bounce/bounce.h"
#include "cost_model.h"
#include "cpu/topology_renderer.h"
#include "engine.h"
#include "error.h"
#include "settings.h"

#ifndef BOUNCE_VERSION_STRING
#define BOUNCE_VERSION_STRING "0.0.0"
#endif

namespace {

thread_local std::string last_error;

template <typename Body>
BounceStatus guarded(Body&& body) {
  try {
    body();
    last_error.clear();
    return BOUNCE_OK;
  } catch (const bounce::Error& e) {
    last_error = e.what();
    return e.status();
  } catch (const std::bad_alloc&) {
    last_error = "out of memory";
    return BOUNCE_ERROR_OUT_OF_MEMORY;
  } catch (const std::exception& e) {
    last_error = std::string("internal error: ") + e.what();
    return BOUNCE_ERROR_INTERNAL;
  } catch (...) {
    last_error = "internal error: unknown exception";
    return BOUNCE_ERROR_INTERNAL;
  }
}

bounce::Engine& engine_of(BounceEngine* engine) {
  bounce::require(engine != nullptr, "engine is NULL");
  return *reinterpret_cast<bounce::Engine*>(engine);
}

template <typename T>
const T& deref(const T* pointer, const char* name) {
  bounce::require(pointer != nullptr, std::string(name) + " is NULL");
  return *pointer;
}

}  // namespace

extern "C" {

const char* bounce_version(void) { return BOUNCE_VERSION_STRING; }
int32_t bounce_api_version(void) { return BOUNCE_API_VERSION; }
const char* bounce_last_error(void) { return last_error.c_str(); }

size_t bounce_settings_size(void) { return sizeof(BounceSettings); }

void bounce_settings_defaults(BounceSettings* out) {
  if (out) *out = bounce::default_settings();
}

const char* bounce_settings_table_json(void) { return bounce::settings_table_json().c_str(); }

BounceStatus bounce_settings_validate(const BounceSettings* settings) {
  return guarded([&] { bounce::validate_settings(deref(settings, "settings")); });
}

BounceStatus bounce_engine_create(const BounceEngineDesc* desc, BounceEngine** out) {
  return guarded([&] {
    bounce::require(out != nullptr, "out is NULL");
    *out = nullptr;
    const BounceEngineDesc defaults{};
    *out = reinterpret_cast<BounceEngine*>(new bounce::Engine(desc ? *desc : defaults));
  });
}

void bounce_engine_destroy(BounceEngine* engine) {
  guarded([&] { delete reinterpret_cast<bounce::Engine*>(engine); });
}

BounceStatus bounce_engine_gl_info(BounceEngine* engine, char* buffer, size_t buffer_size) {
  return guarded([&] {
    const std::string& text = engine_of(engine).gl_description();
    bounce::require(buffer != nullptr && buffer_size > 0, "buffer is NULL or empty");
    std::strncpy(buffer, text.c_str(), buffer_size - 1);
    buffer[buffer_size - 1] = '\0';
  });
}

BounceStatus bounce_mesh_set(BounceEngine* engine, uint64_t mesh_key, const BounceMeshDesc* mesh) {
  return guarded([&] { engine_of(engine).set_mesh(mesh_key, deref(mesh, "mesh")); });
}

BounceStatus bounce_mesh_remove(BounceEngine* engine, uint64_t mesh_key) {
  return guarded([&] { engine_of(engine).remove_mesh(mesh_key); });
}

BounceStatus bounce_texture_set(BounceEngine* engine, uint64_t texture_key, int32_t width, int32_t height,
                                int32_t format, const void* pixels) {
  return guarded([&] { engine_of(engine).set_texture(texture_key, width, height, format, pixels); });
}

BounceStatus bounce_texture_remove(BounceEngine* engine, uint64_t texture_key) {
  return guarded([&] { engine_of(engine).remove_texture(texture_key); });
}

BounceStatus bounce_materials_set(BounceEngine* engine, uint32_t count, const BounceMaterial* materials) {
  return guarded([&] { engine_of(engine).set_materials(count, materials); });
}

BounceStatus bounce_instances_set(BounceEngine* engine, const BounceInstancesDesc* instances) {
  return guarded([&] { engine_of(engine).set_instances(deref(instances, "instances")); });
}

BounceStatus bounce_lights_set(BounceEngine* engine, uint32_t count, const BounceLight* lights) {
  return guarded([&] { engine_of(engine).set_lights(count, lights); });
}

BounceStatus bounce_world_set(BounceEngine* engine, const BounceWorld* world) {
  return guarded([&] { engine_of(engine).set_world(deref(world, "world")); });
}

BounceStatus bounce_scene_stats(BounceEngine* engine, BounceSceneStats* out) {
  return guarded([&] {
    bounce::require(out != nullptr, "out is NULL");
    *out = engine_of(engine).scene_stats();
  });
}

int32_t bounce_aov_channels(int32_t aov) {
  switch (aov) {
    case BOUNCE_AOV_COMBINED:
    case BOUNCE_AOV_TOPOLOGY:
      return 4;
    case BOUNCE_AOV_DIRECT:
    case BOUNCE_AOV_EMISSION:
    case BOUNCE_AOV_ALBEDO:
    case BOUNCE_AOV_NORMAL:
    case BOUNCE_AOV_INDIRECT:
    case BOUNCE_AOV_VPLS:
    case BOUNCE_AOV_SECOND_BOUNCE:
      return 3;
    case BOUNCE_AOV_DEPTH:
      return 1;
    default:
      return 0;
  }
}

const char* bounce_aov_name(int32_t aov) {
  static const char* const names[BOUNCE_AOV_COUNT] = {"Combined", "Direct",   "Emission", "Albedo",        "Normal",
                                                      "Depth",    "Indirect", "VPLs",     "Second Bounce", "Topology"};
  return aov >= 0 && aov < BOUNCE_AOV_COUNT ? names[aov] : "";
}

uint32_t bounce_method_aovs(int32_t method) { return bounce::method_aovs(method); }

BounceStatus bounce_render_start(BounceEngine* engine, const BounceSettings* settings, const BounceCamera* camera) {
  return guarded([&] { engine_of(engine).render_start(deref(settings, "settings"), deref(camera, "camera")); });
}

BounceStatus bounce_render_cancel(BounceEngine* engine) {
  return guarded([&] { engine_of(engine).render_cancel(); });
}

BounceStatus bounce_render_progress(BounceEngine* engine, BounceRenderProgress* out) {
  return guarded([&] {
    bounce::require(out != nullptr, "out is NULL");
    *out = engine_of(engine).progress();
  });
}

BounceStatus bounce_render_wait(BounceEngine* engine, int32_t timeout_ms) {
  return guarded([&] { engine_of(engine).wait(timeout_ms); });
}

BounceStatus bounce_frame_info(BounceEngine* engine, BounceFrameInfo* out) {
  return guarded([&] {
    bounce::require(out != nullptr, "out is NULL");
    *out = engine_of(engine).frame_info();
  });
}

BounceStatus bounce_frame_read(BounceEngine* engine, int32_t aov, float* dst, size_t float_count) {
  return guarded([&] { engine_of(engine).frame_read(aov, dst, float_count); });
}

BounceStatus bounce_topology_info(BounceEngine* engine, BounceTopologyInfo* out) {
  return guarded([&] {
    bounce::require(out != nullptr, "out is NULL");
    *out = BounceTopologyInfo{};
    // Process-wide, so a fresh engine (each F12 render) can tell a cache hit from a build before it renders.
    out->builds = bounce::cpu::topology_builds();
    const auto topology = engine_of(engine).topology();
    if (!topology) return;
    out->available = 1;
    const glm::ivec3 dims = topology->grid.shape.dims;
    out->grid[0] = dims.x;
    out->grid[1] = dims.y;
    out->grid[2] = dims.z;
    out->voxel_size = static_cast<float>(topology->grid.shape.voxel_size);
    out->skeleton_nodes = static_cast<uint32_t>(topology->skeleton.position.size());
    out->segmented_nodes = static_cast<uint32_t>(topology->segmented.original.size());
    out->clusters = topology->cluster_count;
    out->gates = static_cast<uint32_t>(topology->gates.size());
    static_assert(int(bounce::topology::BuildStage::Count) == BOUNCE_TOPOLOGY_STAGES);
    for (int stage = 0; stage < BOUNCE_TOPOLOGY_STAGES; ++stage) {
      std::strncpy(out->stage_names[stage], bounce::topology::build_stage_name(bounce::topology::BuildStage(stage)),
                   sizeof out->stage_names[stage] - 1);
      out->stage_ms[stage] = topology->stage_ms[std::size_t(stage)];
    }
  });
}

BounceStatus bounce_cost_model_directory(const char* directory) {
  return guarded([&] { bounce::CostModel::keep_in(directory ? directory : ""); });
}

}  // extern "C"
