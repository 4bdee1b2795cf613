#pragma once
// The edge term's pass (shaders_glsl/edges.comp; pipelines/model/EdgeEvidence.h): per camera of
// a hypothesis, every model edge that is an occluding contour, a crease or an open mesh's
// border in that camera is sampled along its projection, each unoccluded sample scored by the
// photograph's colour difference across it. It reads the depth map the depth pass drew and the
// reference pyramid, and writes per-workgroup sums the host adds up.

#include <Eigen/Core>
#include <vector>

#include "engine/geometry/SceneGeometry.h"
#include "engine/image/Image.h"
#include "engine/vk/Resources.h"
#include "pipelines/passes/GpuScene.h"
#include "pipelines/passes/ViewTexturePass.h"

namespace vkr {

// One edge of the flattened scene, in its node's frame: endpoints a, b and the third vertex of
// each adjacent triangle, with the sign that turns cross(b − a, c − a) outwards (0 for the
// missing second triangle of a border edge). Vertices are welded by position within a node,
// so a box's faces, each with vertices of their own, share their edges.
struct ModelEdge {
  Eigen::Vector3f a, b, c0, c1;
  float sign0 = 1.0f, sign1 = 0.0f;
  uint32_t node = 0;
};

// Every edge of `geometry` shared by two triangles, or belonging to one (a border). Edges
// inside a flat face (both normals within a degree) are left out: no camera sees them as
// contours or creases. Edges of more than two triangles (non-manifold) are left out too.
std::vector<ModelEdge> FindModelEdges(const SceneGeometry& geometry);

// The statistic's constants for one camera at one level (EdgeEvidence.h).
struct EdgeStatistic {
  double variance = 0.0;  // noise variance of a difference, per channel, [0,1]² scale
  double clutter = 0.1;   // ε
  double hidden = 0.2;    // η
};

class EdgePass {
 public:
  static constexpr uint32_t kSamples = 64;  // edges.comp's points per edge

  // `bindings`: image sets (reference, depth, validity) as ViewTexturePass's; `cameras`: sums
  // kept per camera and hypothesis slot, for `max_batch` slots.
  EdgePass(vk::Device& device, const GpuScene& scene, const std::vector<ModelEdge>& edges, int bindings,
           int cameras, int max_batch, double depth_tolerance);

  // As ViewTexturePass::BindImages (validity VK_NULL_HANDLE: every pixel counts).
  void BindImages(int index, VkImageView reference, VkImageView depth, VkImageView validity);

  // Scores camera `camera`'s edges for hypothesis slot `slot` at `camera_view.level`; `size`:
  // the level's image size in pixels (the full size / 2^level). The depth map must be in
  // DEPTH_READ_ONLY_OPTIMAL and visible to the compute stage. `dump`: keep each edge's sums
  // too (one hypothesis per submission).
  void record(VkCommandBuffer cmd, const ViewCamera& camera_view, const Eigen::Vector2d& size,
              const EdgeStatistic& statistic, int binding, int slot, int camera, bool dump = false) const;
  // Makes the sums visible to the host (once per submission, after every record).
  void record_finish(VkCommandBuffer cmd) const;

  // After the submission: Σ w·log-ratio (x) and Σ w, the scored length in level pixels (y).
  Eigen::Vector2d Result(int slot, int camera) const;
  // After a dump: per camera (row) and edge (column), r = Σ w·log-ratio and g = Σ w.
  Image PerEdge() const;
  bool empty() const { return edge_count_ == 0; }

 private:
  vk::Device* device_;
  const GpuScene* scene_;
  uint32_t edge_count_ = 0, groups_ = 0, lanes_ = 1;
  int cameras_ = 0;
  vk::Buffer edges_, partials_, per_edge_;
  vk::Sampler trilinear_, nearest_;
  vk::DescriptorSetLayout set_layout_;
  vk::PipelineLayout layout_;
  vk::DescriptorPool pool_;
  std::vector<VkDescriptorSet> sets_;
  std::vector<bool> checks_validity_;
  vk::Pipeline pipeline_, validity_pipeline_;
};

}  // namespace vkr
