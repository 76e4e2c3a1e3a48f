// The topology method's indirect visibility on the GPU, for other methods' VPLs (Forward Light Cuts > Indirect
// Shadows: a hybrid of Laurent et al. 2016 and Noel and Biri 2014). Shaders: shaders/topology_visibility/.
//   prepare  - when the topology changes: every grid cell's visibility cluster (its nearest skeleton node's,
//              Sec. IV.B) into a 3-D texture, the gates (Sec. IV.C), each cluster's gate list and the passages
//              between clusters no gates join (native/topology/passages.h) into buffers; the occluders inside
//              clusters (native/topology/occluders.h): each cell's slot as a 3-D texture, its hits as a buffer.
//   execute  - per sample: each pixel's cluster from the G-buffer (pixel_clusters.frag), for the shaders that
//              include visibility.glsl; bind() makes the grid, the gates and that image visible to them.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gl/objects.h"
#include "passes/gbuffer/gbuffer_pass.h"
#include "passes/render_context.h"
#include "topology/topology.h"

namespace bounce {

class TopologyVisibilityPass {
 public:
  TopologyVisibilityPass();
  void prepare(const std::shared_ptr<const topology::Topology>& topology);
  void execute(const RenderContext& context, const GBuffer& gbuffer);
  // The grid, the gates, the passages, the occluders and the pixel clusters, at visibility.glsl's bindings.
  void bind() const;
  // Whether the grid has an empty cell within two voxels of the surface point p along its unit normal n, where
  // visibility.glsl's topology_cluster_at looks first. Thin geometry whose gaps the grid closes (the slats of
  // blinds, the sill under them) has none, and the cluster a light there falls back on is a guess: FlcPass traces
  // such lights' visibility instead.
  bool places(glm::vec3 p, glm::vec3 n) const;
  // Where light that leaves such geometry enters the empty space: the first empty cell along the ray from `origin`
  // along the unit `direction`, in steps of half a voxel from half a voxel up to `reach`; its cluster and its
  // distance from `origin`, or topology::kNoNode when the ray meets no empty cell there.
  struct Entry {
    uint32_t cluster = topology::kNoNode;
    float distance = 0.0f;
  };
  Entry entry_along(glm::vec3 origin, glm::vec3 direction, float reach) const;
  static constexpr GLuint kPixelClustersUnit = 21;

 private:
  uint32_t cluster_at(glm::vec3 p) const;  // of the padded cell holding p; kNoNode outside or solid
  void upload_occluders(const topology::Occluders& occluders, glm::ivec3 padded);
  gl::Program program_;
  std::shared_ptr<const topology::Topology> topology_;
  std::vector<uint32_t> clusters_host_;  // the 3-D texture's cells, for places()
  glm::ivec3 padded_{0};
  glm::vec4 origin_voxel_{0.0f};  // the corner of padded cell (0, 0, 0), the voxel size
  gl::Texture clusters_, pixel_clusters_, occluder_cells_;
  gl::Framebuffer target_;
  gl::Buffer grid_, gates_, cluster_gates_, passages_, occluders_;
  int width_ = 0, height_ = 0;
};

}  // namespace bounce
