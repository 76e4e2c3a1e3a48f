// bounce_reference_render SCENE.bin OUT.raw: the CPU model reference of a scene (flc_reference.h) as an image,
// for scripts/benchmark. The scene comes from benchmarks/cpu_reference_export.py, run inside Blender, as a
// little-endian binary file:
//
//   char[8]  "BNCREF1\n"
//   int32    sizeof(BounceCamera), sizeof(BounceLight)   (checked: the writer used this bounce.h)
//   int32    light_samples (Options)
//   float32  epsilon_fraction (of the scene radius, as flc_epsilon), points (the target count of surface points)
//   BounceCamera
//   int32    light count, then that many BounceLight
//   int64    triangle count, then per triangle 12 float32: three world-space corners, then the albedo
//
// The model is rendered in continuous mode (the limit of FLC's jittered VPLs), with the default seed and every
// core. OUT.raw receives width * height * 4 float32, rows bottom to top: the white-receiver indirect radiance
// (RGB, Image::incident) and coverage (A). Progress goes to stderr.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "reference/flc_reference.h"

namespace {

using bounce::reference::Triangle;

class Reader {
 public:
  explicit Reader(const char* path) : in_(path, std::ios::binary) {
    if (!in_) throw std::runtime_error(std::string("cannot open ") + path);
  }
  template <typename T>
  T read() {
    T value;
    bytes(&value, sizeof(T));
    return value;
  }
  void bytes(void* out, std::size_t size) {
    if (!in_.read(static_cast<char*>(out), static_cast<std::streamsize>(size)))
      throw std::runtime_error("the scene file ends early");
  }

 private:
  std::ifstream in_;
};

int run(const char* scene_path, const char* out_path) {
  Reader in(scene_path);
  char magic[8];
  in.bytes(magic, sizeof(magic));
  if (std::memcmp(magic, "BNCREF1\n", 8) != 0) throw std::runtime_error("not a Bounce reference scene file");
  if (in.read<int32_t>() != int32_t(sizeof(BounceCamera)) || in.read<int32_t>() != int32_t(sizeof(BounceLight)))
    throw std::runtime_error("the scene file was written for another bounce.h");
  bounce::reference::Options options;
  options.light_samples = in.read<int32_t>();
  const float epsilon_fraction = in.read<float>();
  const float points = in.read<float>();
  const auto camera = in.read<BounceCamera>();
  std::vector<BounceLight> lights(static_cast<std::size_t>(in.read<int32_t>()));
  in.bytes(lights.data(), lights.size() * sizeof(BounceLight));
  std::vector<Triangle> triangles(static_cast<std::size_t>(in.read<int64_t>()));
  for (Triangle& t : triangles) {
    float v[12];
    in.bytes(v, sizeof(v));
    for (int c = 0; c < 3; ++c) t.p[c] = {v[3 * c], v[3 * c + 1], v[3 * c + 2]};
    t.albedo = {v[9], v[10], v[11]};
  }

  const auto start = std::chrono::steady_clock::now();
  const bounce::reference::Scene scene(std::move(triangles), std::move(lights));
  // The scene radius as the renderer takes it (FlcPass): half the bounding box diagonal.
  options.epsilon = epsilon_fraction * 0.5f * scene.diagonal();
  double area = 0.0;
  for (const Triangle& t : scene.triangles()) area += 0.5 * glm::length(glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]));
  options.points_per_unit_area = area > 0.0 ? static_cast<float>(points / area) : 0.0f;
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
