#pragma once
// Host-side culling for the view-specific texture pass. Lavapipe shades a rasterised texel at
// full cost even where the shader returns at once (it runs divergent branches under a mask:
// bench/RESULTS.md, "Back-facing triangles"), so the only way not to pay for texels a camera
// cannot see is not to shade them. Per hypothesis and camera, clusters of triangles that lie
// wholly outside the camera's frustum or behind its near plane, or that are flat and turn
// their back on it, go to a pipeline that only writes weight 0 — what the full shader writes
// there — so the view layers, and the likelihood, stay bit-identical. The tests are
// conservative by a margin far above float rounding: a cluster near a boundary is shaded.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "engine/geometry/SceneGeometry.h"

namespace vkr {

// A range of the scene's index buffer (GpuScene), one vkCmdDrawIndexed.
struct IndexRun {
  uint32_t first = 0, count = 0;
};

// What one camera's view pass draws: `shaded` with the full shader, `unseen` with weight 0.
// Together they cover every index once, so every chart texel is written.
struct ViewDraws {
  std::vector<IndexRun> shaded, unseen;
  double unseen_area = 0.0;  // share of the charts' area drawn unseen: what culling saves this camera
};

class ViewCulling {
 public:
  explicit ViewCulling(const SceneGeometry& geometry);

  // `clip_from_world`: the camera's projection (Projection.h, near plane at `near`).
  ViewDraws Classify(const std::vector<Eigen::Matrix4d>& world_from_node, const Eigen::Matrix4d& clip_from_world,
                     const Eigen::Vector3d& centre, double near) const;

  // Everything shaded: what the pass drew before culling (and draws with culling off).
  ViewDraws ShadeAll() const;

  int cluster_count() const { return int(clusters_.size()); }

 private:
  // Consecutive triangles of one face.
  struct Cluster {
    IndexRun indices;
    int node = 0;
    double area = 0.0;                  // in the atlas, as a share of all clusters' area
    std::vector<Eigen::Vector3d> hull;  // points whose convex hull holds the cluster (node frame)
    bool flat = false;                  // one plane and one normal for every vertex
    Eigen::Vector3d normal{0, 0, 0};    // node frame, as the vertices carry it (when flat)
  };
  bool Unseen(const Cluster& cluster, const Eigen::Matrix4d& world_from_node, const Eigen::Matrix4d& clip_from_world,
              const Eigen::Vector3d& centre, double near) const;

  std::vector<Cluster> clusters_;
  uint32_t index_count_ = 0;
};

}  // namespace vkr
