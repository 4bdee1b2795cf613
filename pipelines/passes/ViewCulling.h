#pragma once
// Host-side culling for the view-specific texture pass. Lavapipe shades a rasterised texel at
// full cost even where the shader returns at once (it runs divergent branches under a mask:
// bench/RESULTS.md, "Back-facing triangles"), so the only way not to pay for texels a camera
// cannot see is not to shade them. Per hypothesis and camera, clusters of triangles that lie
// wholly outside the camera's frustum or behind its near plane, or that are flat and turn
// their back on it, go to a pipeline that only writes weight 0 — what the full shader writes
// there — so the view layers, and the likelihood, stay bit-identical. The tests are
// conservative by a margin far above float rounding: a cluster near a boundary is shaded.
// A large cluster partly in view (the ground, which takes most of the atlas and most of
// whose chart a camera may not see) is drawn in parts: the full shader inside a rectangle of
// the atlas that holds all of it the frustum can see, weight 0 outside.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "engine/geometry/SceneGeometry.h"

namespace vkr {

// A range of the scene's index buffer (GpuScene), one vkCmdDrawIndexed.
struct IndexRun {
  uint32_t first = 0, count = 0;
};

// A run drawn in parts: with the full shader inside [u0, u1] × [v0, v1] (atlas coordinates,
// [0,1]²), which holds every texel of the run the camera's frustum can see, and with weight
// 0 outside it. ViewTexturePass widens it to whole texels and a margin.
struct PartialRun {
  IndexRun indices;
  double u0 = 0, v0 = 0, u1 = 1, v1 = 1;
};

// What one camera's view pass draws: `shaded` with the full shader, `unseen` with weight 0,
// `partial` in parts. Together they cover every index once, so every chart texel is written.
struct ViewDraws {
  std::vector<IndexRun> shaded, unseen;
  std::vector<PartialRun> partial;
  // Share of the charts' area drawn with weight 0: what culling saves this camera (for a
  // partial run, the part of its atlas bounds outside the shaded rectangle).
  double unseen_area = 0.0;
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
    // Large clusters only (may be drawn in parts): each triangle's corners (node frame) and
    // their atlas coordinates, three per triangle, and the atlas bounds of them all.
    std::vector<Eigen::Vector3d> corners;
    std::vector<Eigen::Vector2d> corner_uvs;
    Eigen::Vector2d uv_lo{0, 0}, uv_hi{0, 0};
  };
  bool Unseen(const Cluster& cluster, const Eigen::Matrix4d& world_from_node, const Eigen::Matrix4d& clip_from_world,
              const Eigen::Vector3d& centre, double near) const;
  // The atlas rectangle of the part of `cluster` inside the frustum (each triangle clipped
  // against the frustum's planes, widened by the test margin), as PartialRun holds it;
  // false when no part of it is inside.
  bool VisibleRect(const Cluster& cluster, const Eigen::Matrix4d& clip_from_node, double near, PartialRun* rect) const;

  std::vector<Cluster> clusters_;
  uint32_t index_count_ = 0;
};

}  // namespace vkr
