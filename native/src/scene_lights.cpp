#include "scene_lights.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/gtc/type_ptr.hpp>

#include "passes/light_views.h"
#include "radiometry.h"
#include "sampling.h"

namespace bounce {

namespace shared_glsl {
using glm::atan;
using glm::cross;
using glm::dot;
using glm::length;
using glm::vec2;
using glm::vec3;
#define EQUIRECT_INLINE inline
#include "common/equirect_shared.glsl"
#undef EQUIRECT_INLINE
#define EMITTERS_INLINE inline
#include "common/emitter_occluders_shared.glsl"
#undef EMITTERS_INLINE
}  // namespace shared_glsl

bool emitter_between(std::span<const EmitterOccluder> emitters, glm::vec3 y, glm::vec3 x, float margin) {
  const glm::vec3 d = x - y;
  const float length_d = glm::length(d);
  if (!(length_d > 2.0f * margin)) return false;
  const float t_min = margin / length_d, t_max = 1.0f - t_min;
  return std::any_of(emitters.begin(), emitters.end(), [&](const EmitterOccluder& e) {
    return shared_glsl::triangle_crosses_segment(glm::vec3(e.a), glm::vec3(e.b), glm::vec3(e.c), y, d, t_min, t_max);
  });
}

namespace {

// The world's importance table is the environment averaged down to at most this many texels a side (power is
// kept; a sun of one pixel keeps its share, spread over one table texel: 0.7 degrees).
constexpr int kWorldTableWidth = 512, kWorldTableHeight = 256;
// And at least this many, so that the guided draws (guide_world) can tell the bins of direction apart, even under a
// uniform world: two texels a side per bin (sphere_bins).
constexpr int kWorldTableMinWidth = 2 * sphere_bins::kSectors, kWorldTableMinHeight = 2 * sphere_bins::kRings;

// The pixels [first, last) of an image `pixels` wide that table texel `texel` of `texels` covers; in a table finer
// than the image, the pixel its centre falls in (a texel that straddles two pixels would otherwise take the first,
// and the image's colours would shift by up to a texel).
std::pair<int, int> pixel_span(int texel, int texels, int pixels) {
  if (pixels < texels) {
    const int centre = std::min((2 * texel + 1) * pixels / (2 * texels), pixels - 1);
    return {centre, centre + 1};
  }
  return {texel * pixels / texels, (texel + 1) * pixels / texels};
}

// The weight by which lights are drawn: radiance summed over channels (a pure red light still counts).
float weight(glm::vec3 radiance) { return std::max(0.0f, radiance.r + radiance.g + radiance.b); }

// The mean of `texture` over the triangle (uv0, uv1, uv2) of texture space, as the camera sees it (bilinear):
// 64 stratified samples per texel the triangle covers, 16 to 4096, so that a screen's two triangles carry the
// picture's mean colour.
glm::vec3 triangle_mean(const TextureData& texture, glm::vec2 uv0, glm::vec2 uv1, glm::vec2 uv2) {
  const glm::vec2 e1 = uv1 - uv0, e2 = uv2 - uv0;
  const float texels = 0.5f * std::abs(e1.x * e2.y - e1.y * e2.x) * float(texture.width) * float(texture.height);
  const int count = std::isfinite(texels) ? int(std::clamp(64.0f * texels, 16.0f, 4096.0f)) : 16;
  glm::vec3 sum(0.0f);
  for (int i = 0; i < count; ++i) {
    const glm::vec3 p = uniform_triangle_point(glm::vec3(uv0, 0.0f), glm::vec3(uv1, 0.0f), glm::vec3(uv2, 0.0f),
                                               r2_point(uint32_t(i), glm::vec2(0.0f)));
    sum += glm::vec3(texture_sample(texture, glm::vec2(p)));
  }
  return sum / float(count);
}

}  // namespace

SceneLights::WorldTable SceneLights::table_of(std::vector<double> cdf, std::size_t width) {
  WorldTable table;
  for (std::size_t r = 0; r * width < cdf.size(); ++r) table.row_cdf.push_back(cdf[r * width]);
  table.cdf = std::move(cdf);
  return table;
}

glm::vec2 equirect_uv(glm::vec3 e) { return shared_glsl::equirect_uv(e); }

glm::vec3 equirect_direction(glm::vec2 uv) {
  const float phi = (0.5f - uv.x) * 2.0f * kPi, elevation = (uv.y - 0.5f) * kPi;
  return {std::cos(phi) * std::cos(elevation), std::sin(phi) * std::cos(elevation), std::sin(elevation)};
}

WorldRadiance::WorldRadiance(const BounceWorld& world, const TextureData* environment)
    : background_(glm::make_vec3(world.background)),
      environment_(environment && environment->width > 0 && environment->height > 0 ? environment : nullptr),
      world_to_environment_(glm::make_mat3(world.world_to_environment)) {}

glm::vec3 WorldRadiance::operator()(glm::vec3 direction) const {
  if (!environment_) return background_;
  const glm::vec3 e = world_to_environment_ * direction;
  return background_ * glm::vec3(texture_sample(*environment_, equirect_uv(e)));
}

void SceneLights::update(const GpuScene& scene) {
  if (scene.geometry_version() != geometry_version_) {
    geometry_version_ = scene.geometry_version();
    emitters_.clear();
    emitter_cdf_.assign(1, 0.0);
    for (const GpuScene::DrawnPart& part : scene.drawn_parts()) {
      const glm::vec3 emission = glm::max(glm::make_vec3(part.material.emission), glm::vec3(0.0f));
      if (!(weight(emission) > 0.0f)) continue;
      const TextureData* texture = scene.texture_data(part.material.emission_texture);
      const glm::mat4& m = part.instance.object_to_world;
      for (uint32_t v = part.submesh.first_vertex; v + 2 < part.submesh.first_vertex + part.submesh.vertex_count;
           v += 3) {
        const Vertex* vertex = &part.mesh.vertices[v];
        glm::vec3 corner[3];
        for (int k = 0; k < 3; ++k) corner[k] = glm::vec3(m * glm::vec4(glm::make_vec3(vertex[k].position), 1.0f));
        const float area = 0.5f * glm::length(glm::cross(corner[1] - corner[0], corner[2] - corner[0]));
        if (!(area > 0.0f) || !std::isfinite(area)) continue;  // the transform collapsed it
        const glm::vec3 radiance =
            texture ? emission * triangle_mean(*texture, glm::make_vec2(vertex[0].uv), glm::make_vec2(vertex[1].uv),
                                               glm::make_vec2(vertex[2].uv))
                    : emission;
        if (!(weight(radiance) > 0.0f)) continue;
        emitters_.push_back({corner[0], corner[1], corner[2], radiance});
        emitter_cdf_.push_back(emitter_cdf_.back() + double(weight(radiance)) * double(area));
      }
    }
  }
  if (scene.world_version() != world_version_) {
    world_version_ = scene.world_version();
    const WorldRadiance world(scene.world(), scene.texture_data(scene.world().environment_texture));
    const TextureData* env = world.environment();
    world_texels_.clear();
    world_peak_ = 0.0f;
    std::vector<double> world_cdf(1, 0.0);
    world_width_ = std::size_t(std::max(env ? std::min(env->width, kWorldTableWidth) : 1, kWorldTableMinWidth));
    const int width = int(world_width_);
    const int height = std::max(env ? std::min(env->height, kWorldTableHeight) : 1, kWorldTableMinHeight);
    for (int row = 0; row < height; ++row) {
      const float v0 = float(row) / float(height), v1 = float(row + 1) / float(height);
      const float z0 = std::sin((v0 - 0.5f) * kPi), z1 = std::sin((v1 - 0.5f) * kPi);
      for (int column = 0; column < width; ++column) {
        glm::vec3 radiance = world.background();
        if (env) {  // the mean of the environment's pixels in this table texel
          const auto [x0, x1] = pixel_span(column, width, env->width);
          const auto [y0, y1] = pixel_span(row, height, env->height);
          glm::dvec3 sum(0.0);
          for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) sum += glm::dvec3(glm::vec3(texture_texel(*env, x, y)));
          radiance *= glm::vec3(sum / double(std::max((x1 - x0) * (y1 - y0), 1)));
        }
        radiance = glm::max(radiance, glm::vec3(0.0f));
        if (!std::isfinite(weight(radiance))) radiance = glm::vec3(0.0f);
        const float u0 = float(column) / float(width), u1 = float(column + 1) / float(width);
        const double solid_angle = double(u1 - u0) * 2.0 * kPi * double(z1 - z0);
        world_texels_.push_back({radiance, u0, u1, z0, z1});
        world_peak_ = std::max(world_peak_, weight(radiance));
        world_cdf.push_back(world_cdf.back() + double(weight(radiance)) * solid_angle);
      }
    }
    world_table_ = table_of(std::move(world_cdf), world_width_);
    // The table's directions are the environment's; the lights need the world's (normalized once drawn: a Mapping
    // node may scale unevenly).
    world_to_environment_ = glm::make_mat3(scene.world().world_to_environment);
    environment_to_world_ = glm::inverse(world_to_environment_);
    world_bins_.clear();
    for (const WorldTexel& texel : world_texels_) {
      const float z = 0.5f * (texel.z0 + texel.z1);
      const glm::vec2 centre(0.5f * (texel.u0 + texel.u1), std::asin(std::clamp(z, -1.0f, 1.0f)) / kPi + 0.5f);
      world_bins_.push_back(
          uint8_t(sphere_bins::of(glm::normalize(environment_to_world_ * equirect_direction(centre)))));
    }
    guided_table_ = {};
  }
}

bool SceneLights::world_lights(const GpuScene& scene, const BounceSettings& settings) {
  update(scene);
  const double total = world_table_.total();
  return settings.world_lights > 0 && total > 0.0 && std::isfinite(total);
}

void SceneLights::guide_world(std::span<const float> reach) {
  guided_table_ = {};
  guide_factors_.clear();
  const std::vector<double>& cdf = world_table_.cdf;
  if (reach.size() != std::size_t(sphere_bins::kCount) || world_texels_.empty() || cdf.size() < 2) return;
  const double total = cdf.back();
  double expected = 0.0;  // the reach's mean under the table's density
  for (std::size_t t = 0; t < world_texels_.size(); ++t)
    expected += (cdf[t + 1] - cdf[t]) * double(reach[world_bins_[t]]);
  expected /= total;
  if (!(expected > 0.0) || !std::isfinite(expected)) return;
  for (const float r : reach)
    guide_factors_.push_back(float((1.0 - kGuidedShare) + kGuidedShare * double(r > 0.0f ? r : 0.0f) / expected));
  std::vector<double> guided(1, 0.0);
  for (std::size_t t = 0; t < world_texels_.size(); ++t)
    guided.push_back(guided.back() + (cdf[t + 1] - cdf[t]) * double(guide_factors_[world_bins_[t]]));
  guided_table_ = table_of(guided, world_width_);
}

SceneLights::WorldDensity SceneLights::world_density(glm::vec3 w) const {
  const double total = world_table_.total();
  if (world_texels_.empty() || !(total > 0.0) || !std::isfinite(total)) return {0.0f, glm::vec3(0.0f)};
  const glm::vec2 uv = equirect_uv(glm::normalize(world_to_environment_ * w));
  const std::size_t width = world_width_, height = world_texels_.size() / width;
  const std::size_t column = std::min(std::size_t(std::max(uv.x, 0.0f) * float(width)), width - 1);
  const std::size_t row = std::min(std::size_t(std::max(uv.y, 0.0f) * float(height)), height - 1);
  const WorldTexel& texel = world_texels_[row * width + column];
  return {float(double(weight(texel.radiance)) / total), texel.radiance};
}

std::optional<SceneLights::WorldDirection> SceneLights::draw_world(glm::vec2 u) const {
  return draw_from(world_table_, {}, u);
}

std::optional<SceneLights::WorldDirection> SceneLights::draw_from(const WorldTable& table,
                                                                  std::span<const float> factors, glm::vec2 u) const {
  const std::vector<double>& world_cdf = table.cdf;
  const double total = table.total();
  if (world_texels_.empty() || !(total > 0.0) || !std::isfinite(total)) return std::nullopt;
  // A row (elevation) by u.y from the rows' marginal, then a texel of it by u.x: both coordinates stratify.
  const std::size_t width = world_width_;
  const std::vector<double>& row_cdf = table.row_cdf;
  const double row_target = double(u.y) * total;
  const std::size_t row = find_in_cdf(row_cdf, row_target);
  const double row_weight = row_cdf[row + 1] - row_cdf[row];
  const double target = row_cdf[row] + double(u.x) * row_weight;
  // Searched within the row's own width + 1 entries (a search per direction and point on the ray-traced paths).
  const std::size_t t =
      row * width + find_in_cdf(std::span<const double>(world_cdf).subspan(row * width, width + 1), target);
  const WorldTexel& texel = world_texels_[t];
  const double span = world_cdf[t + 1] - world_cdf[t];
  // The fractions of the targets within the row's and the texel's shares place the direction in the texel.
  const auto fraction = [](double x, double lo, double size) {
    return size > 0.0 ? float(std::clamp((x - lo) / size, 0.0, 1.0)) : 0.5f;
  };
  const float z = texel.z0 + fraction(row_target, row_cdf[row], row_weight) * (texel.z1 - texel.z0);
  const float phi_u = texel.u0 + fraction(target, world_cdf[t], span) * (texel.u1 - texel.u0);
  const float elevation_v = std::asin(std::clamp(z, -1.0f, 1.0f)) / kPi + 0.5f;
  const glm::vec3 direction = glm::normalize(environment_to_world_ * equirect_direction({phi_u, elevation_v}));
  const double factor = factors.empty() ? 1.0 : double(factors[world_bins_[t]]);
  return WorldDirection{direction, texel.radiance, float(double(weight(texel.radiance)) * factor / total),
                        float(factor)};
}

BounceLight world_sun(glm::vec3 direction, glm::vec3 irradiance) {
  BounceLight light{};
  light.type = BOUNCE_LIGHT_SUN;
  light.cast_shadow = 1;
  const glm::vec3 x = any_perpendicular(direction), y = glm::cross(direction, x);
  for (int i = 0; i < 3; ++i) {
    light.axis_x[i] = x[i];
    light.axis_y[i] = y[i];
    light.axis_z[i] = direction[i];
    light.intensity[i] = irradiance[i];
  }
  return light;
}

void SceneLights::add_world(const BounceSettings& settings, uint32_t sample, uint32_t seed) {
  world_guide_factors_.clear();
  const int count = settings.world_lights;
  if (count <= 0) return;
  const glm::vec2 rotation(hash_to_unit(hash_combine(seed, 201)), hash_to_unit(hash_combine(seed, 202)));
  for (int k = 0; k < count; ++k) {
    // The (sample * count + k)-th point of one R2 sequence: the render's directions stay stratified as a whole.
    const glm::vec2 u = r2_point(sample * uint32_t(count) + uint32_t(k), rotation);
    const std::optional<WorldDirection> drawn =
        guide_factors_.empty() ? draw_world(u) : draw_from(guided_table_, guide_factors_, u);
    if (!drawn) return;
    // Irradiance L / (K p).
    lights_.push_back(world_sun(drawn->direction, drawn->radiance / (float(count) * drawn->pdf)));
    world_guide_factors_.push_back(drawn->guide_factor);
  }
}

void SceneLights::add_emitters(const BounceSettings& settings, uint32_t sample, uint32_t seed) {
  occluders_.clear();
  const std::size_t count = std::size_t(std::max(settings.emission_lights, 0));
  const double total = emitter_cdf_.back();
  if (count == 0 || emitters_.empty() || !(total > 0.0) || !std::isfinite(total)) return;
  const auto add_occluder = [&](const Emitter& e) {
    occluders_.push_back({glm::vec4(e.a, 0.0f), glm::vec4(e.b, 0.0f), glm::vec4(e.c, 0.0f)});
  };
  if (emitters_.size() <= count) {
    for (const Emitter& e : emitters_) {
      lights_.push_back(make_triangle_light(e.a, e.b, e.c, e.radiance));
      add_occluder(e);
    }
    return;
  }
  // Systematic sampling by power: K evenly spaced targets, one random offset per sample. A triangle drawn n times
  // is one light n times as bright.
  const double offset = double(hash_to_unit(hash_combine(hash_combine(seed, 301), sample)));
  std::size_t previous = SIZE_MAX;
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t t = find_in_cdf(emitter_cdf_, (double(k) + offset) / double(count) * total);
    const Emitter& e = emitters_[t];
    const double p = (emitter_cdf_[t + 1] - emitter_cdf_[t]) / total;
    const glm::vec3 radiance = e.radiance * float(1.0 / (double(count) * p));
    if (t == previous) {
      for (int i = 0; i < 3; ++i) lights_.back().intensity[i] += radiance[i];
      continue;
    }
    lights_.push_back(make_triangle_light(e.a, e.b, e.c, radiance));
    add_occluder(e);
    previous = t;
  }
}

const std::vector<BounceLight>& SceneLights::sample(const GpuScene& scene, const BounceSettings& settings,
                                                    uint32_t sample, uint32_t seed) {
  update(scene);
  lights_ = scene.lamps();
  lamp_count_ = lights_.size();
  add_world(settings, sample, seed);
  world_count_ = lights_.size() - lamp_count_;
  add_emitters(settings, sample, seed);
  // The range policy of the caller's lights (scene_data.h) holds for these too: a 1e30 emitter drawn with a small
  // probability would overflow float32.
  for (std::size_t i = lamp_count_; i < lights_.size(); ++i) dim_to_max_intensity(lights_[i].intensity);
  return lights_;
}

}  // namespace bounce
