// bounce_reference_render SCENE.bin OUT.raw: the CPU model reference of a scene (flc_reference.h) as an image,
// for scripts/benchmark. The scene comes from benchmarks/cpu_reference_export.py (reference/scene_file.h).
//
// The model is rendered in continuous mode (the limit of FLC's jittered VPLs), with the default seed and every
// core. OUT.raw receives width * height * 4 float32, rows bottom to top: the white-receiver indirect radiance
// (RGB, Image::incident) and coverage (A). Progress goes to stderr.
#include <chrono>
#include <cstdio>
#include <exception>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "reference/flc_reference.h"
#include "reference/scene_file.h"

namespace {

using bounce::reference::Triangle;

int run(const char* scene_path, const char* out_path) {
  bounce::reference::SceneFile file = bounce::reference::read_scene_file(scene_path);
  const BounceCamera& camera = file.camera;
  bounce::reference::Options options;
  options.light_samples = file.light_samples;

  const auto start = std::chrono::steady_clock::now();
  const bounce::reference::Scene scene(std::move(file.triangles), std::move(file.lights));
  // The scene radius as the renderer takes it (FlcPass): half the bounding box diagonal.
  options.epsilon = file.epsilon_fraction * 0.5f * scene.diagonal();
  double area = 0.0;
  for (const Triangle& t : scene.triangles()) area += 0.5 * glm::length(glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]));
  options.points_per_unit_area = area > 0.0 ? static_cast<float>(file.points / area) : 0.0f;
  std::fprintf(stderr, "bounce_reference_render: %zu triangles, %zu lights, %.0f m^2, %dx%d pixels\n",
               scene.triangles().size(), scene.lights().size(), area, camera.width, camera.height);
  const bounce::reference::Image image = render(scene, camera, bounce::reference::Mode::continuous, options);
  std::fprintf(stderr, "bounce_reference_render: %.1f s\n",
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());

  std::vector<float> rgba(image.incident.size() * 4);
  for (std::size_t i = 0; i < image.incident.size(); ++i) {
    for (int c = 0; c < 3; ++c) rgba[4 * i + std::size_t(c)] = image.incident[i][c];
    rgba[4 * i + 3] = image.covered[i];
  }
  std::ofstream out(out_path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(rgba.data()), static_cast<std::streamsize>(rgba.size() * sizeof(float)));
  if (!out) throw std::runtime_error(std::string("cannot write ") + out_path);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: bounce_reference_render SCENE.bin OUT.raw\n");
    return 2;
  }
  try {
    return run(argv[1], argv[2]);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "bounce_reference_render: %s\n", error.what());
    return 1;
  }
}
