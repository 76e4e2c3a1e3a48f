#include "passes/topology_visibility/topology_visibility_pass.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#include <glm/common.hpp>
#include <glm/gtc/packing.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>
#include <glm/vector_relational.hpp>

#include "error.h"
#include "gl/shader.h"
#include "topology/shared_glsl.h"

namespace bounce {
namespace {

constexpr GLuint kGridBlock = 6;
constexpr GLuint kGatesBinding = 10;
constexpr GLuint kClusterGatesBinding = 11;
constexpr GLuint kPassagesBinding = 13;
constexpr GLuint kOccludersBinding = 14;
constexpr GLuint kOccluderCellsUnit = 22;
constexpr GLuint kClustersUnit = 20;

struct GridBlock {  // std140 mirror of visibility.glsl's TopologyGrid
  glm::vec4 origin_voxel;
  glm::ivec4 dims;
};
struct GpuGate {  // std430 mirror of visibility.glsl's TopologyGate
  glm::vec4 centre_half_u, normal_half_v, axis_u;
  glm::uvec4 clusters;
};

}  // namespace

TopologyVisibilityPass::TopologyVisibilityPass()
    : program_(gl::build_program({{GL_VERTEX_SHADER, "common/fullscreen.vert"},
                                  {GL_FRAGMENT_SHADER, "topology_visibility/pixel_clusters.frag"}})),
      grid_(gl::make_buffer(sizeof(GridBlock), nullptr)) {}

void TopologyVisibilityPass::prepare(const std::shared_ptr<const topology::Topology>& topology) {
  if (topology == topology_) return;
  topology_ = topology;
  const topology::GridShape& shape = topology->grid.shape;
  const glm::ivec3 padded = shape.padded();
  // Padded cells, x fastest: the layout of the topology's arrays and of a 3-D texture alike.
  clusters_host_ = topology::voxel_clusters_split_at_gates(*topology);
  const std::vector<uint32_t>& clusters = clusters_host_;
  padded_ = padded;
  GLuint texture = 0;
  glCreateTextures(GL_TEXTURE_3D, 1, &texture);
  clusters_ = gl::Texture(texture);
  glTextureStorage3D(texture, 1, GL_R32UI, padded.x, padded.y, padded.z);
  glTextureSubImage3D(texture, 0, 0, 0, 0, padded.x, padded.y, padded.z, GL_RED_INTEGER, GL_UNSIGNED_INT,
                      clusters.data());
  glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);

  const glm::dvec3 corner = shape.origin - shape.voxel_size;  // padded cell (0, 0, 0)
  origin_voxel_ = glm::vec4(glm::vec3(corner), float(shape.voxel_size));
  const GridBlock grid{origin_voxel_, glm::ivec4(padded, int(topology->cluster_count))};
  glNamedBufferSubData(grid_.id(), 0, sizeof grid, &grid);

  // A gate that needs a ray is marked (clusters.z): the GPU confirms a crossing through it by a march through the
  // voxels (topology_voxels_clear).
  std::vector<GpuGate> gates;
  std::vector<std::vector<uint32_t>> of_cluster(topology->cluster_count);
  for (const topology::Gate& gate : topology->gates) {
    for (uint32_t c : gate.clusters)
      if (c < topology->cluster_count) of_cluster[c].push_back(uint32_t(gates.size()));
    gates.push_back({glm::vec4(gate.centre, gate.half_u), glm::vec4(gate.normal, gate.half_v),
                     glm::vec4(gate.axis_u, 0.0f),
                     glm::uvec4(gate.clusters[0], gate.clusters[1], gate.needs_ray() ? 1u : 0u, 0u)});
  }
  // Three words per cluster (first index, count, component), then the gate indices of each cluster in turn.
  std::vector<uint32_t> table(3 * of_cluster.size());
  for (std::size_t c = 0; c < of_cluster.size(); ++c) {
    table[3 * c] = uint32_t(table.size());
    table[3 * c + 1] = uint32_t(of_cluster[c].size());
    table[3 * c + 2] = topology->component[c];
    table.insert(table.end(), of_cluster[c].begin(), of_cluster[c].end());
  }
  // GL buffers may not be empty.
  if (gates.empty()) gates.push_back({});
  if (table.empty()) table.push_back(0);
  // The slots, then per passage its rectangle (as a GpuGate's first three vectors) and its shares, as float bits;
  // one 0 stands for none (visibility.glsl).
  std::vector<uint32_t> passages = topology->passages.slot;
  for (const topology::Passage& passage : topology->passages.passages) {
    const topology::Gate& gate = passage.gate;
    const std::array<float, 12> rectangle{gate.centre.x, gate.centre.y, gate.centre.z, gate.half_u,
                                          gate.normal.x, gate.normal.y, gate.normal.z, gate.half_v,
                                          gate.axis_u.x, gate.axis_u.y, gate.axis_u.z, 0.0f};
    for (const float value : rectangle) passages.push_back(std::bit_cast<uint32_t>(value));
    for (const float share : passage.share) passages.push_back(std::bit_cast<uint32_t>(share));
  }
  if (passages.size() < 2) passages.assign(1, 0u);
  gates_ = gl::make_buffer(gates.size() * sizeof(GpuGate), gates.data());
  cluster_gates_ = gl::make_buffer(table.size() * sizeof(uint32_t), table.data());
  passages_ = gl::make_buffer(passages.size() * sizeof(uint32_t), passages.data());
  upload_occluders(topology->occluders, padded);
  gl::check("uploading the topology's visibility");
}

void TopologyVisibilityPass::upload_occluders(const topology::Occluders& occluders, glm::ivec3 padded) {
  // Per padded cell its slot (a 1 x 1 x 1 texture when there are none), then per slot and bin a word: the hit's
  // plane offset as a half float, its normal in the octahedral map at 6 bits per coordinate, the share of the bin it
  // hides in the top 4 bits (in 15ths) (visibility.glsl).
  const bool any = !occluders.slot.empty();
  const glm::ivec3 dims = any ? padded : glm::ivec3(1);
  GLuint texture = 0;
  glCreateTextures(GL_TEXTURE_3D, 1, &texture);
  occluder_cells_ = gl::Texture(texture);
  glTextureStorage3D(texture, 1, GL_R32UI, dims.x, dims.y, dims.z);
  const uint32_t none = 0;
  glTextureSubImage3D(texture, 0, 0, 0, 0, dims.x, dims.y, dims.z, GL_RED_INTEGER, GL_UNSIGNED_INT,
                      any ? occluders.slot.data() : &none);
  glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  std::vector<uint32_t> words(occluders.hits.size() + 1, 0u);
  for (std::size_t i = 0; i < occluders.hits.size(); ++i) {
    const topology::Occluders::Hit& hit = occluders.hits[i];
    // No surface: a plane no light is behind (and no normal).
    const bool surface = std::isfinite(hit.distance);
    const glm::vec2 octahedral = surface ? topology::shared::octahedral_from_direction(hit.normal) : glm::vec2(0.0f);
    const glm::uvec2 coordinates(glm::round(glm::clamp(0.5f * octahedral + 0.5f, 0.0f, 1.0f) * 63.0f));
    const float plane = surface ? hit.plane : -std::numeric_limits<float>::infinity();
    words[i] = (glm::packHalf2x16(glm::vec2(plane, 0.0f)) & 0xFFFFu) | (coordinates.x << 16) | (coordinates.y << 22) |
               (uint32_t(std::lround(std::clamp(hit.share, 0.0f, 1.0f) * 15.0f)) << 28);
  }
  occluders_ = gl::make_buffer(words.size() * sizeof(uint32_t), words.data());
}

void TopologyVisibilityPass::execute(const RenderContext& context, const GBuffer& gbuffer) {
  StageScope scope(context.timer, Stage::TopologyVisibility);
  if (width_ != context.width || height_ != context.height) {
    pixel_clusters_ = gl::make_texture_2d(GL_R32UI, context.width, context.height);
    target_ = gl::make_framebuffer({pixel_clusters_.id()}, 0);
    width_ = context.width;
    height_ = context.height;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, target_.id());
  glViewport(0, 0, width_, height_);
  gbuffer.bind_for_reading();
  bind();
  glUseProgram(program_.id());
  const glm::vec4 eye =
      context.orthographic ? glm::vec4(context.camera_forward, 1.0f) : glm::vec4(context.camera_position, 0.0f);
  glUniform4fv(0, 1, &eye[0]);
  draw_fullscreen_triangle();
  gl::check("finding the pixels' visibility clusters");
}

uint32_t TopologyVisibilityPass::cluster_at(glm::vec3 p) const {
  const glm::vec3 cell = glm::floor((p - glm::vec3(origin_voxel_)) / origin_voxel_.w);
  if (!glm::all(glm::greaterThanEqual(cell, glm::vec3(0.0f))) || !glm::all(glm::lessThan(cell, glm::vec3(padded_))))
    return topology::kNoNode;
  const glm::ivec3 c(cell);
  return clusters_host_[(std::size_t(c.z) * std::size_t(padded_.y) + std::size_t(c.y)) * std::size_t(padded_.x) +
                        std::size_t(c.x)];
}

TopologyVisibilityPass::Entry TopologyVisibilityPass::entry_along(glm::vec3 origin, glm::vec3 direction,
                                                                  float reach) const {
  const float voxel = origin_voxel_.w;
  if (clusters_host_.empty() || !(voxel > 0.0f)) return {};
  const float steps = std::min(reach / voxel, 2.0f * float(padded_.x + padded_.y + padded_.z));
  for (float step = 0.5f; step <= steps; step += 0.5f) {
    const uint32_t cluster = cluster_at(origin + step * voxel * direction);
    if (cluster != topology::kNoNode) return {cluster, step * voxel};
  }
  return {};
}

bool TopologyVisibilityPass::places(glm::vec3 p, glm::vec3 n) const {
  return clusters_host_.empty() || entry_along(p, n, 2.0f * origin_voxel_.w).cluster != topology::kNoNode;
}

void TopologyVisibilityPass::bind() const {
  glBindBufferBase(GL_UNIFORM_BUFFER, kGridBlock, grid_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kGatesBinding, gates_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kClusterGatesBinding, cluster_gates_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kPassagesBinding, passages_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kOccludersBinding, occluders_.id());
  glBindTextureUnit(kOccluderCellsUnit, occluder_cells_.id());
  glBindTextureUnit(kClustersUnit, clusters_.id());
  glBindTextureUnit(kPixelClustersUnit, pixel_clusters_.id());
}

}  // namespace bounce
