// bounce_scene_bench SCENE.bin [--methods DIRECT,FLC,SSVP,TOPOLOGY] [--samples N] [--repeats R]
//                    [--set NAME=VALUE]... [--csv OUT.csv]
//
// Time per progressive sample of each method on a scene exported from Blender (reference/scene_file.h), through
// the C API alone: no Blender, so it runs on machines that have none, e.g. a GPU server
// (BOUNCE_EGL_PLATFORM=device for NVIDIA's EGL). Each method gets its own engine; a first render of one sample
// pays the one-off costs (shader compilation, the topology's precomputation) and is reported apart; then R renders
// of N samples are timed, and the median per sample is reported, with each stage's GPU time (timer queries) per
// sample. Prints a Markdown table; --csv writes one row per (method, repeat, stage), the input of
// benchmarks/scene_bench_plot.py. Each triangle keeps its exported albedo, quantized to 8 levels per channel so
// that the scene needs at most 512 materials.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bounce/bounce.h"
#include "reference/scene_file.h"

namespace {

struct Options {
  std::string scene_path;
  std::vector<std::string> methods = {"DIRECT", "FLC", "SSVP", "TOPOLOGY"};
  int samples = 16;
  int repeats = 3;
  std::vector<std::pair<std::string, std::string>> overrides;
  std::string csv_path;
};

void check(BounceStatus status, const char* what) {
  if (status != BOUNCE_OK) throw std::runtime_error(std::string(what) + ": " + bounce_last_error());
}

// The value of an ENUM setting's item from its identifier, in settings.def's items ("ID:Label:Description|..."),
// or -1.
int32_t enum_value(const std::string& items, const std::string& identifier) {
  int32_t index = 0;
  for (std::size_t start = 0; start < items.size(); ++index) {
    const std::size_t end = std::min(items.find('|', start), items.size());
    if (items.compare(start, items.find(':', start) - start, identifier) == 0) return index;
    start = end + 1;
  }
  return -1;
}

double number_of(const std::string& name, const std::string& value) {
  try {
    std::size_t used = 0;
    const double number = std::stod(value, &used);
    if (used == value.size()) return number;
  } catch (const std::exception&) {
  }
  throw std::runtime_error("setting '" + name + "': '" + value + "' is neither a number nor one of its items");
}

// Sets a setting of the one table (settings.def) by name, from a number or an ENUM item's identifier ("FLC");
// bounce_settings_validate checks its range.
void set_setting(BounceSettings& settings, const std::string& name, const std::string& value) {
#define BOUNCE_SETTING(ctype, glsl_type, kind, setting, label, def, min, max, soft_min, soft_max, flags, group, items, \
                       desc)                                                                                           \
  if (name == #setting) {                                                                                              \
    const int32_t item = enum_value(items, value);                                                                     \
    settings.setting = static_cast<ctype>(item >= 0 ? double(item) : number_of(name, value));                          \
    return;                                                                                                            \
  }
#include "bounce/settings.def"
#undef BOUNCE_SETTING
  throw std::runtime_error("unknown setting '" + name + "'");
}

void upload_scene(BounceEngine* engine, const bounce::reference::SceneFile& scene) {
  std::vector<float> positions;
  std::vector<uint32_t> indices;
  std::vector<int32_t> slots;
  std::map<int32_t, int32_t> slot_of_albedo;
  std::vector<BounceMaterial> materials;
  positions.reserve(scene.triangles.size() * 9);
  for (const auto& t : scene.triangles) {
    int32_t key = 0;
    for (int c = 0; c < 3; ++c) key = key * 8 + std::clamp(static_cast<int32_t>(t.albedo[c] * 8.0f), 0, 7);
    const auto [found, added] = slot_of_albedo.emplace(key, static_cast<int32_t>(materials.size()));
    if (added) {
      BounceMaterial material{};
      for (int c = 0; c < 3; ++c) material.base_color[c] = t.albedo[c];
      material.alpha = 1.0f;
      material.alpha_threshold = 0.5f;
      material.double_sided = 1;
      materials.push_back(material);
    }
    slots.push_back(found->second);
    for (const auto& p : t.p) {
      indices.push_back(static_cast<uint32_t>(positions.size() / 3));
      positions.insert(positions.end(), {p.x, p.y, p.z});
    }
  }
  BounceMeshDesc mesh{};
  mesh.vertex_count = static_cast<uint32_t>(positions.size() / 3);
  mesh.positions = positions.data();
  mesh.triangle_count = static_cast<uint32_t>(scene.triangles.size());
  mesh.triangles = indices.data();
  mesh.triangle_slots = slots.data();
  check(bounce_mesh_set(engine, 1, &mesh), "bounce_mesh_set");
  check(bounce_materials_set(engine, static_cast<uint32_t>(materials.size()), materials.data()),
        "bounce_materials_set");
  const uint64_t key = 1;
  const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::vector<uint32_t> slot_materials(materials.size());
  for (std::size_t i = 0; i < slot_materials.size(); ++i) slot_materials[i] = static_cast<uint32_t>(i);
  const uint32_t offset = 0, count = static_cast<uint32_t>(slot_materials.size());
  const BounceInstancesDesc instances{1, &key, identity, &offset, &count, count, slot_materials.data()};
  check(bounce_instances_set(engine, &instances), "bounce_instances_set");
  check(bounce_lights_set(engine, static_cast<uint32_t>(scene.lights.size()), scene.lights.data()),
        "bounce_lights_set");
}

struct Timing {
  double wall_ms = 0.0;                 // the whole render, per sample
  uint64_t vpls = 0;                    // of the last sample
  std::string plan;                     // AUTO: what it rendered and why (BounceFrameInfo::plan)
  std::vector<BounceStageTime> stages;  // per sample
};

Timing render(BounceEngine* engine, const BounceSettings& settings, const BounceCamera& camera) {
  const auto start = std::chrono::steady_clock::now();
  check(bounce_render_start(engine, &settings, &camera), "bounce_render_start");
  check(bounce_render_wait(engine, -1), "rendering");
  Timing timing;
  timing.wall_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / settings.samples;
  BounceFrameInfo info{};
  check(bounce_frame_info(engine, &info), "bounce_frame_info");
  timing.vpls = info.vpl_count;
  timing.plan = info.plan;
  for (int i = 0; i < info.stage_count; ++i) {
    BounceStageTime stage = info.stages[i];
    stage.gpu_ms /= settings.samples;
    stage.cpu_ms /= settings.samples;
    timing.stages.push_back(stage);
  }
  return timing;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

int run(const Options& options) {
  const bounce::reference::SceneFile scene = bounce::reference::read_scene_file(options.scene_path);
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> csv_file(nullptr, std::fclose);
  if (!options.csv_path.empty()) {
    csv_file.reset(std::fopen(options.csv_path.c_str(), "w"));
    if (!csv_file) throw std::runtime_error("cannot write " + options.csv_path);
    std::fprintf(csv_file.get(),
                 "scene,method,width,height,samples,repeat,stage,gpu_ms_per_sample,cpu_ms_per_sample\n");
  }
  std::FILE* csv = csv_file.get();
  std::string scene_name = options.scene_path.substr(options.scene_path.find_last_of('/') + 1);
  scene_name = scene_name.substr(0, scene_name.find('.'));
  std::printf("%s: %zu triangles, %zu lights, %dx%d, %d samples x %d repeats\n\n", scene_name.c_str(),
              scene.triangles.size(), scene.lights.size(), scene.camera.width, scene.camera.height, options.samples,
              options.repeats);
  std::printf("| method | first render (s) | ms per sample | VPLs | stages, GPU ms per sample (CPU where marked) |\n");
  std::printf("| --- | ---: | ---: | ---: | --- |\n");
  std::vector<std::string> plans;  // AUTO's, printed under the table
  for (const std::string& method : options.methods) {
    BounceSettings settings;
    bounce_settings_defaults(&settings);
    set_setting(settings, "method", method);
    settings.samples = options.samples;
    for (const auto& [name, value] : options.overrides) set_setting(settings, name, value);
    check(bounce_settings_validate(&settings), "settings");

    BounceEngine* engine = nullptr;
    check(bounce_engine_create(nullptr, &engine), "bounce_engine_create");
    try {
      char gl[256] = {};
      check(bounce_engine_gl_info(engine, gl, sizeof(gl)), "bounce_engine_gl_info");
      std::fprintf(stderr, "bounce_scene_bench: %s on %s\n", method.c_str(), gl);
      upload_scene(engine, scene);
      BounceSettings first = settings;
      first.samples = 1;
      const double first_s = render(engine, first, scene.camera).wall_ms / 1000.0;
      std::vector<double> walls;
      std::vector<Timing> timings;
      for (int r = 0; r < options.repeats; ++r) {
        timings.push_back(render(engine, settings, scene.camera));
        walls.push_back(timings.back().wall_ms);
        if (csv)
          for (const BounceStageTime& stage : timings.back().stages)
            std::fprintf(csv, "%s,%s,%d,%d,%d,%d,\"%s\",%.4f,%.4f\n", scene_name.c_str(), method.c_str(),
                         scene.camera.width, scene.camera.height, settings.samples, r, stage.name, stage.gpu_ms,
                         stage.cpu_ms);
        if (csv)
          std::fprintf(csv, "%s,%s,%d,%d,%d,%d,wall,,%.4f\n", scene_name.c_str(), method.c_str(), scene.camera.width,
                       scene.camera.height, settings.samples, r, timings.back().wall_ms);
      }
      const double wall = median(walls);
      const Timing& typical = *std::min_element(timings.begin(), timings.end(), [&](const Timing& a, const Timing& b) {
        return std::abs(a.wall_ms - wall) < std::abs(b.wall_ms - wall);
      });
      // The stages of the median repeat, the largest first; a stage with no GPU time (Topology's, on the CPU)
      // counts its time on the render thread.
      std::vector<BounceStageTime> stages = typical.stages;
      const auto cost = [](const BounceStageTime& stage) { return stage.gpu_ms > 0.0 ? stage.gpu_ms : stage.cpu_ms; };
      std::sort(stages.begin(), stages.end(), [&](const auto& a, const auto& b) { return cost(a) > cost(b); });
      std::string stage_text;
      for (const BounceStageTime& stage : stages) {
        if (cost(stage) < 0.05) continue;
        char item[96];
        std::snprintf(item, sizeof(item), "%s%s %.2f%s", stage_text.empty() ? "" : ", ", stage.name, cost(stage),
                      stage.gpu_ms > 0.0 ? "" : " (CPU)");
        stage_text += item;
      }
      std::printf("| %s | %.2f | %.2f | %llu | %s |\n", method.c_str(), first_s, wall,
                  static_cast<unsigned long long>(typical.vpls), stage_text.c_str());
      if (!typical.plan.empty()) plans.push_back(method + ": " + typical.plan);
      std::fflush(stdout);
    } catch (...) {
      bounce_engine_destroy(engine);
      throw;
    }
    bounce_engine_destroy(engine);
  }
  for (const std::string& plan : plans) std::printf("\n%s\n", plan.c_str());
  return 0;
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t end; (end = text.find(separator, start)) != std::string::npos; start = end + 1)
    parts.push_back(text.substr(start, end - start));
  parts.push_back(text.substr(start));
  return parts;
}

Options parse(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--methods") {
      options.methods = split(value(), ',');
    } else if (arg == "--samples") {
      options.samples = std::max(1, std::stoi(value()));
    } else if (arg == "--repeats") {
      options.repeats = std::max(1, std::stoi(value()));
    } else if (arg == "--csv") {
      options.csv_path = value();
    } else if (arg == "--set") {
      const std::string assignment = value();
      const std::size_t equals = assignment.find('=');
      if (equals == std::string::npos) throw std::runtime_error("--set takes NAME=VALUE");
      options.overrides.emplace_back(assignment.substr(0, equals), assignment.substr(equals + 1));
    } else if (options.scene_path.empty() && arg.rfind("--", 0) != 0) {
      options.scene_path = arg;
    } else {
      throw std::runtime_error("unknown argument '" + arg + "'");
    }
  }
  if (options.scene_path.empty()) throw std::runtime_error("no scene file given");
  return options;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& error) {
    std::fprintf(stderr, "bounce_scene_bench: %s\n", error.what());
    std::fprintf(stderr,
                 "usage: bounce_scene_bench SCENE.bin [--methods DIRECT,FLC,SSVP,TOPOLOGY] [--samples N] "
                 "[--repeats R] [--set NAME=VALUE]... [--csv OUT.csv]\n");
    return 1;
  }
}
