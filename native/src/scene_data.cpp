#include "scene_data.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "error.h"
#include "sampling.h"

namespace bounce {

// Numeric range policy. Bounce computes in float32: rays (Embree asserts on coordinates beyond 1.8e18 and Debian's
// build keeps its assertions), shadow and reflective shadow maps fitted over the scene's bounds (whose depth maths
// squares distances: the square of 2e19 is no float), depth buffers and sums of light over many VPLs. Inputs that
// are finite but beyond what those resolve are handled here, once, when the scene is validated, and counted in
// BounceSceneStats so that the add-on reports them:
//   - a triangle with a corner (in its mesh's own space) beyond kMaxCoordinate from the origin is dropped
//     (out_of_range_triangles), and so is an instance whose world bounds reach beyond it (out_of_range_instances;
//     GpuScene applies within_range to them): neither is drawn, lit, traced nor counted in the scene's bounds;
//   - a point, spot or area light placed beyond kMaxCoordinate is skipped (out_of_range_lights); a sun has no
//     position and is kept;
//   - a light brighter than kMaxIntensity is dimmed to it, its colour kept, and radii and area sizes beyond
//     kMaxCoordinate are cut to it (clamped_lights); float texels, materials' emission and the world's factor are
//     clamped to [0, kMaxIntensity] and non-finite ones zeroed (their products stay finite).
// 1e9 m (a million kilometres, where float32 steps by 64 m) keeps planet-sized scenes while leaving nine orders of
// magnitude to Embree's limit and the squares of distances; 1e15 W/sr times the largest area or sun disk the range
// allows (~1e19 m^2) stays a thousand times below FLT_MAX.

bool within_range(glm::vec3 p) {
  return std::abs(p.x) <= kMaxCoordinate && std::abs(p.y) <= kMaxCoordinate && std::abs(p.z) <= kMaxCoordinate;
}

void dim_to_max_intensity(float (&intensity)[3]) {
  const float peak = std::max({intensity[0], intensity[1], intensity[2]});
  const bool finite = std::isfinite(peak);
  const float dimming = finite && peak > kMaxIntensity ? kMaxIntensity / peak : 1.0f;
  for (float& c : intensity) c = !(c > 0.0f) ? 0.0f : finite ? c * dimming : kMaxIntensity;
}

namespace {

bool finite3(const float* v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

std::string key_name(const char* what, uint64_t key) { return std::string(what) + " " + std::to_string(key); }

glm::dvec3 load3(const float* v) { return {v[0], v[1], v[2]}; }

// Shadow cube maps are rendered and read in the light's frame, which must be orthonormal (a sheared or scaled
// object matrix is not): Gram-Schmidt from -z (the emission axis), then x; world axes where degenerate.
void orthonormalize_frame(BounceLight& light) {
  glm::dvec3 z = load3(light.axis_z), x = load3(light.axis_x);
  if (!(glm::length(z) > 1e-12)) z = {0, 0, 1};
  z = glm::normalize(z);
  x -= glm::dot(x, z) * z;
  if (!(glm::length(x) > 1e-9)) x = glm::cross(std::abs(z.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0), z);
  x = glm::normalize(x);
  const glm::dvec3 y = glm::cross(z, x);
  for (int i = 0; i < 3; ++i) {
    light.axis_x[i] = static_cast<float>(x[i]);
    light.axis_y[i] = static_cast<float>(y[i]);
    light.axis_z[i] = static_cast<float>(z[i]);
  }
}

const std::array<float, 256>& srgb_to_linear() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const float c = float(i) / 255.0f;
      t[std::size_t(i)] = c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
    }
    return t;
  }();
  return table;
}

}  // namespace

std::shared_ptr<const MeshData> prepare_mesh(uint64_t key, const BounceMeshDesc& desc) {
  require(desc.triangle_count == 0 || (desc.triangles && desc.positions),
          key_name("mesh", key) + ": triangles or positions is NULL");
  require(desc.triangle_count <= (1u << 28), key_name("mesh", key) + ": more than 2^28 triangles");
  auto mesh = std::make_shared<MeshData>();
  const uint32_t n = desc.triangle_count;

  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  if (desc.triangle_slots) {
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return desc.triangle_slots[a] < desc.triangle_slots[b]; });
  }
  mesh->vertices.reserve(3ull * n);
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (uint32_t t : order) {
    const uint32_t* tri = desc.triangles + 3ull * t;
    for (int c = 0; c < 3; ++c) {
      if (tri[c] >= desc.vertex_count)
        fail(BOUNCE_ERROR_INVALID_ARGUMENT, key_name("mesh", key) + ": triangle " + std::to_string(t) +
                                                " refers to vertex " + std::to_string(tri[c]) + " of " +
                                                std::to_string(desc.vertex_count));
    }
    const float* p[3] = {desc.positions + 3ull * tri[0], desc.positions + 3ull * tri[1],
                         desc.positions + 3ull * tri[2]};
    if (!finite3(p[0]) || !finite3(p[1]) || !finite3(p[2])) {
      ++mesh->dropped_triangles;
      continue;
    }
    if (!within_range(glm::make_vec3(p[0])) || !within_range(glm::make_vec3(p[1])) ||
        !within_range(glm::make_vec3(p[2]))) {
      ++mesh->out_of_range_triangles;
      continue;
    }
    const glm::dvec3 cross = glm::cross(load3(p[1]) - load3(p[0]), load3(p[2]) - load3(p[0]));
    const double twice_area = glm::length(cross);
    if (!(twice_area > 0.0) || !std::isfinite(twice_area)) {
      ++mesh->dropped_triangles;
      continue;
    }
    const glm::vec3 face_normal = glm::vec3(cross / twice_area);
    const int32_t slot = desc.triangle_slots ? std::max(desc.triangle_slots[t], 0) : 0;
    if (mesh->submeshes.empty() || mesh->submeshes.back().slot != slot)
      mesh->submeshes.push_back({slot, static_cast<uint32_t>(mesh->vertices.size()), 0});
    for (int c = 0; c < 3; ++c) {
      Vertex v{};
      std::memcpy(v.position, p[c], sizeof v.position);
      v.random = pcg_hash(tri[c] ^ 0xa511e9b3u);
      glm::vec3 normal = face_normal;
      if (desc.corner_normals) {
        const float* cn = desc.corner_normals + 9ull * t + 3ull * c;
        const glm::vec3 given(cn[0], cn[1], cn[2]);
        const float length = glm::length(given);
        if (std::isfinite(length) && length > 1e-12f) normal = given / length;
      }
      std::memcpy(v.normal, &normal[0], sizeof v.normal);
      if (desc.corner_uvs) {
        const float* uv = desc.corner_uvs + 6ull * t + 2ull * c;
        v.uv[0] = std::isfinite(uv[0]) ? uv[0] : 0.0f;
        v.uv[1] = std::isfinite(uv[1]) ? uv[1] : 0.0f;
      }
      lo = glm::min(lo, glm::vec3(p[c][0], p[c][1], p[c][2]));
      hi = glm::max(hi, glm::vec3(p[c][0], p[c][1], p[c][2]));
      mesh->vertices.push_back(v);
    }
    mesh->submeshes.back().vertex_count += 3;
  }
  if (!mesh->vertices.empty()) {
    mesh->bounds_min = lo;
    mesh->bounds_max = hi;
  }
  return mesh;
}

std::shared_ptr<const InstanceList> prepare_instances(const BounceInstancesDesc& desc) {
  require(desc.count == 0 || (desc.mesh_keys && desc.matrices && desc.slot_offsets && desc.slot_counts),
          "instances: an array is NULL");
  require(desc.slot_material_count == 0 || desc.slot_materials, "instances: slot_materials is NULL");
  auto list = std::make_shared<InstanceList>();
  list->instances.reserve(desc.count);
  for (uint32_t i = 0; i < desc.count; ++i) {
    const uint64_t end = uint64_t(desc.slot_offsets[i]) + desc.slot_counts[i];
    if (end > desc.slot_material_count)
      fail(BOUNCE_ERROR_INVALID_ARGUMENT, "instance " + std::to_string(i) + ": slots " +
                                              std::to_string(desc.slot_offsets[i]) + "+" +
                                              std::to_string(desc.slot_counts[i]) + " overrun slot_materials");
    InstanceData instance;
    instance.mesh_key = desc.mesh_keys[i];
    instance.object_to_world = glm::make_mat4(desc.matrices + 16ull * i);
    const float det = glm::determinant(glm::mat3(instance.object_to_world));
    bool finite = std::isfinite(det) && det != 0.0f;
    for (int k = 0; k < 16 && finite; ++k) finite = std::isfinite(desc.matrices[16ull * i + k]);
    if (!finite) {
      ++list->dropped;
      continue;
    }
    instance.normal_to_world = glm::mat4(glm::inverseTranspose(glm::mat3(instance.object_to_world)));
    const uint32_t* slots = desc.slot_materials + desc.slot_offsets[i];
    instance.slot_materials.assign(slots, slots + desc.slot_counts[i]);
    list->instances.push_back(std::move(instance));
  }
  return list;
}

std::array<glm::vec3, 3> triangle_light_corners(const BounceLight& light) {
  const glm::vec3 a = glm::make_vec3(light.position), x = glm::make_vec3(light.axis_x),
                  y = glm::make_vec3(light.axis_y);
  return {a, a + light.triangle[0] * x + light.triangle[1] * y, a + light.triangle[2] * x + light.triangle[3] * y};
}

float triangle_light_area(const BounceLight& light) {
  return 0.5f * std::abs(light.triangle[0] * light.triangle[3] - light.triangle[1] * light.triangle[2]);
}

float emitting_area(const BounceLight& light) {
  switch (light.type) {
    case BOUNCE_LIGHT_AREA_TRIANGLE:
      return 2.0f * triangle_light_area(light);
    case BOUNCE_LIGHT_AREA_RECT:
      return 4.0f * light.half_size[0] * light.half_size[1];
    default:
      return 3.14159265f * light.half_size[0] * light.half_size[1];
  }
}

BounceLight make_triangle_light(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 radiance) {
  BounceLight light{};
  light.type = BOUNCE_LIGHT_AREA_TRIANGLE;
  light.cast_shadow = 1;
  const glm::vec3 x = glm::normalize(b - a), z = glm::normalize(glm::cross(b - a, c - a)), y = glm::cross(z, x);
  for (int i = 0; i < 3; ++i) {
    light.position[i] = a[i];
    light.axis_x[i] = x[i];
    light.axis_y[i] = y[i];
    light.axis_z[i] = z[i];
    light.intensity[i] = radiance[i];
  }
  light.triangle[0] = glm::length(b - a);
  light.triangle[1] = 0.0f;
  light.triangle[2] = glm::dot(c - a, x);
  light.triangle[3] = glm::dot(c - a, y);
  return light;
}

LightList prepare_lights(uint32_t count, const BounceLight* lights) {
  require(count == 0 || lights, "lights: NULL array");
  LightList list;
  for (uint32_t i = 0; i < count; ++i) {
    BounceLight light = lights[i];
    require(light.type >= BOUNCE_LIGHT_POINT && light.type <= BOUNCE_LIGHT_AREA_TRIANGLE,
            "light " + std::to_string(i) + ": unknown type " + std::to_string(light.type));
    const bool finite =
        finite3(light.position) && finite3(light.axis_x) && finite3(light.axis_y) && finite3(light.axis_z) &&
        finite3(light.intensity) && std::isfinite(light.radius) && std::isfinite(light.half_size[0]) &&
        std::isfinite(light.half_size[1]) && std::isfinite(light.spot_half_angle) && std::isfinite(light.spot_blend) &&
        std::isfinite(light.sun_angle) && std::isfinite(light.triangle[0]) && std::isfinite(light.triangle[1]) &&
        std::isfinite(light.triangle[2]) && std::isfinite(light.triangle[3]);
    const float peak = std::max({light.intensity[0], light.intensity[1], light.intensity[2]});
    const bool area = light.type == BOUNCE_LIGHT_AREA_RECT || light.type == BOUNCE_LIGHT_AREA_ELLIPSE;
    const bool triangle = light.type == BOUNCE_LIGHT_AREA_TRIANGLE;
    if (!finite || !(peak > 0.0f) || (area && !(light.half_size[0] > 0.0f && light.half_size[1] > 0.0f)) ||
        (triangle && !(triangle_light_area(light) > 0.0f))) {
      ++list.skipped;
      continue;
    }
    if (light.type != BOUNCE_LIGHT_SUN && !within_range(glm::make_vec3(light.position))) {
      ++list.out_of_range;
      continue;
    }
    const bool too_large = peak > kMaxIntensity || light.radius > kMaxCoordinate ||
                           light.half_size[0] > kMaxCoordinate || light.half_size[1] > kMaxCoordinate ||
                           std::any_of(std::begin(light.triangle), std::end(light.triangle),
                                       [](float c) { return std::abs(c) > kMaxCoordinate; });
    list.clamped += too_large ? 1 : 0;
    dim_to_max_intensity(light.intensity);
    for (float& h : light.half_size) h = std::min(h, kMaxCoordinate);
    for (float& c : light.triangle) c = std::clamp(c, -kMaxCoordinate, kMaxCoordinate);
    orthonormalize_frame(light);
    light.radius = std::clamp(light.radius, 0.0f, kMaxCoordinate);
    light.spot_half_angle = std::clamp(light.spot_half_angle, 0.0f, 3.14159265f);
    light.spot_blend = std::clamp(light.spot_blend, 0.0f, 1.0f);
    light.sun_angle = std::clamp(light.sun_angle, 0.0f, 3.14159265f);
    list.lights.push_back(light);
    list.source_index.push_back(i);
  }
  return list;
}

std::vector<BounceMaterial> prepare_materials(uint32_t count, const BounceMaterial* materials) {
  require(count == 0 || materials, "materials: NULL array");
  std::vector<BounceMaterial> out(materials, materials + count);
  for (BounceMaterial& m : out) {
    for (float& c : m.base_color) c = std::isfinite(c) ? std::clamp(c, 0.0f, 1.0f) : 0.0f;
    for (float& c : m.emission) c = std::isfinite(c) ? std::clamp(c, 0.0f, kMaxIntensity) : 0.0f;
    m.alpha = std::isfinite(m.alpha) ? std::clamp(m.alpha, 0.0f, 1.0f) : 1.0f;
    m.alpha_threshold = std::isfinite(m.alpha_threshold) ? std::clamp(m.alpha_threshold, 0.0f, 1.0f) : 0.5f;
  }
  return out;
}

std::shared_ptr<const TextureData> prepare_texture(uint64_t key, int32_t width, int32_t height, int32_t format,
                                                   const void* pixels) {
  require(key != BOUNCE_NO_TEXTURE, "texture key 0 is reserved for 'no texture'");
  require(width > 0 && height > 0 && width <= 32768 && height <= 32768,
          key_name("texture", key) + ": size " + std::to_string(width) + "x" + std::to_string(height) +
              " is outside 1..32768");
  require(format >= BOUNCE_TEXTURE_RGBA8_SRGB && format <= BOUNCE_TEXTURE_RGBA32F,
          key_name("texture", key) + ": unknown format " + std::to_string(format));
  require(pixels, key_name("texture", key) + ": pixels is NULL");
  auto texture = std::make_shared<TextureData>();
  texture->width = width;
  texture->height = height;
  texture->format = format;
  const std::size_t texel_bytes = format == BOUNCE_TEXTURE_RGBA32F ? 16 : 4;
  const auto* bytes = static_cast<const unsigned char*>(pixels);
  texture->bytes.assign(bytes, bytes + texel_bytes * std::size_t(width) * std::size_t(height));
  if (format == BOUNCE_TEXTURE_RGBA32F) {
    auto* texels = reinterpret_cast<float*>(texture->bytes.data());
    // Radiance and albedo as lights take them (kMaxIntensity): an environment texel times the world's factor,
    // both at most 1e15, stays finite in float32, where 1e30 x 1e30 would not.
    for (std::size_t i = 0; i < std::size_t(width) * height * 4; ++i)
      texels[i] = std::isfinite(texels[i]) ? std::clamp(texels[i], 0.0f, kMaxIntensity) : 0.0f;
  }
  return texture;
}

BounceMaterial default_material() {
  BounceMaterial m{};
  m.base_color[0] = m.base_color[1] = m.base_color[2] = 0.8f;
  m.alpha = 1.0f;
  m.alpha_threshold = 0.5f;
  m.double_sided = 1;
  return m;
}

glm::vec4 texture_texel(const TextureData& texture, int x, int y) {
  x = ((x % texture.width) + texture.width) % texture.width;  // GL_REPEAT, as the GPU samples
  y = ((y % texture.height) + texture.height) % texture.height;
  const std::size_t index = std::size_t(y) * std::size_t(texture.width) + std::size_t(x);
  if (texture.format == BOUNCE_TEXTURE_RGBA32F) {
    const auto* f = reinterpret_cast<const float*>(texture.bytes.data()) + 4 * index;
    return {f[0], f[1], f[2], f[3]};
  }
  const unsigned char* b = texture.bytes.data() + 4 * index;
  if (texture.format == BOUNCE_TEXTURE_RGBA8_SRGB)
    return {srgb_to_linear()[b[0]], srgb_to_linear()[b[1]], srgb_to_linear()[b[2]], float(b[3]) / 255.0f};
  return glm::vec4(b[0], b[1], b[2], b[3]) / 255.0f;
}

glm::vec4 texture_sample(const TextureData& texture, glm::vec2 uv) {
  const float x = uv.x * float(texture.width) - 0.5f, y = uv.y * float(texture.height) - 0.5f;
  if (!std::isfinite(x) || !std::isfinite(y) || std::abs(x) > 1e8f || std::abs(y) > 1e8f)
    return texture_texel(texture, 0, 0);
  const float fx = std::floor(x), fy = std::floor(y);
  const int x0 = int(fx), y0 = int(fy);
  const float tx = x - fx, ty = y - fy;
  return (1 - ty) * ((1 - tx) * texture_texel(texture, x0, y0) + tx * texture_texel(texture, x0 + 1, y0)) +
         ty * ((1 - tx) * texture_texel(texture, x0, y0 + 1) + tx * texture_texel(texture, x0 + 1, y0 + 1));
}

}  // namespace bounce
