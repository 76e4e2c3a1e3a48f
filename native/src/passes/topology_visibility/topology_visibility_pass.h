// The topology method's indirect visibility on the GPU, for other methods' VPLs (Forward Light Cuts > Indirect
// Shadows: a hybrid of Laurent et al. 2016 and Noel and Biri 2014). Shaders: shaders/topology_visibility/.
//   prepare  - when the topology changes: every grid cell's visibility cluster (its nearest skeleton node's,
//              Sec. IV.B) into a 3-D texture, the gates (Sec. IV.C), each cluster's gate list and the passages
//              between clusters no gates join (native/topology/passages.h) into buffers; the occluders inside
//              clusters (native/topology/occluders.h): each cell's slot as a 3-D texture, its hits as a buffer.
//   execute  - per sample: each pixel's cluster from the G-buffer (pixel_clusters.frag), for the shaders that
//              include visibility.glsl; bind() makes the grid, the gates and that image visible to them.
#pragma once

#include <memory>

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
  static constexpr GLuint kPixelClustersUnit = 21;

 private:
  void upload_occluders(const topology::Occluders& occluders, glm::ivec3 padded);
  gl::Program program_;
  std::shared_ptr<const topology::Topology> topology_;
  gl::Texture clusters_, pixel_clusters_, occluder_cells_;
  gl::Framebuffer target_;
  gl::Buffer grid_, gates_, cluster_gates_, passages_, occluders_;
  int width_ = 0, height_ = 0;
};

}  // namespace bounce
