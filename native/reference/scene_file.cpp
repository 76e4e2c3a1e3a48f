#include "reference/scene_file.h"

#include <cstring>
#include <fstream>
#include <stdexcept>

namespace bounce::reference {
namespace {

class Reader {
 public:
  explicit Reader(const std::string& path) : in_(path, std::ios::binary) {
    if (!in_) throw std::runtime_error("cannot open " + path);
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

}  // namespace

SceneFile read_scene_file(const std::string& path) {
  Reader in(path);
  char magic[8];
  in.bytes(magic, sizeof(magic));
  if (std::memcmp(magic, "BNCREF1\n", 8) != 0) throw std::runtime_error(path + " is not a Bounce scene file");
  if (in.read<int32_t>() != int32_t(sizeof(BounceCamera)) || in.read<int32_t>() != int32_t(sizeof(BounceLight)))
    throw std::runtime_error(path + " was written for another bounce.h");
  SceneFile scene;
  scene.light_samples = in.read<int32_t>();
  scene.epsilon_fraction = in.read<float>();
  scene.points = in.read<float>();
  scene.camera = in.read<BounceCamera>();
  scene.lights.resize(static_cast<std::size_t>(in.read<int32_t>()));
  in.bytes(scene.lights.data(), scene.lights.size() * sizeof(BounceLight));
  scene.triangles.resize(static_cast<std::size_t>(in.read<int64_t>()));
  for (Triangle& t : scene.triangles) {
    float v[12];
    in.bytes(v, sizeof(v));
    for (int c = 0; c < 3; ++c) t.p[c] = {v[3 * c], v[3 * c + 1], v[3 * c + 2]};
    t.albedo = {v[9], v[10], v[11]};
  }
  return scene;
}

}  // namespace bounce::reference
