#pragma once
// A CPU reference of the surface-space photo-consistency likelihood
// (docs/internals/LIKELIHOOD.md; thesis §5–7), written to be independent of the GPU path: no
// rasterisation of the scene and no shadow maps. Texels are found by testing atlas texel centres
// against the flattened triangles in atlas-UV space, interior points by analytic inside tests of
// the unit primitives, visibility by casting the segment texel → camera centre against every
// triangle of the scene (Möller–Trumbore), colours by host bilinear sampling of the float pyramid
// (optionally prefiltered across levels, as the GPU's mip-mapped sampler). Everything is in double
// precision. The tests compare the GPU's reduced scalars with it.

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "engine/geometry/SceneGeometry.h"
#include "engine/image/Image.h"
#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "pipelines/model/Evaluation.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"
#include "tests/common/TestFiles.h"

namespace vkr::test {

// What became of one atlas texel.
enum class TexelState : uint8_t { OffSurface, Interior, Exterior };

// Per-texel results, row-major over the level's atlas (A_l × A_l).
struct ReferenceTexels {
  int side = 0;                     // A_l = atlas >> level
  std::vector<TexelState> state;
  std::vector<int> chart;           // the atlas chart (GpuVertex::face) of on-surface texels, else -1
  std::vector<uint8_t> views;       // n_t: cameras that see the texel (exterior texels)
  std::vector<double> deviation;    // χ_t, the robust loss (Evaluation.h); 0 unless n_t ≥ 2
  std::vector<double> dof;          // d_t, its expectation under the noise model; 0 unless n_t ≥ 2
  std::vector<uint8_t> outliers;    // views with e² > K
  // Per camera c, per texel: rgb = colour seen (as stored), a = weight w_i; all 0 where c
  // does not see the texel (the GPU's view-specific textures, SurfaceDump::view_textures).
  std::vector<Image> view_textures;
};

// One camera's sample of a texel, as the composite gets it.
struct ViewSample {
  Eigen::Vector3d colour;  // as stored, [0,1]
  double weight = 0.0;     // w_i > 0
  double texture = 0.0;    // |∇I| where it was sampled
  int camera = 0;          // for the photometric correction
  double mass = 1.0;       // full-resolution pixels the sample averages (≥ 1)
};

// The composite's statistic of one texel seen by ≥ 2 views (Evaluation.h), in double
// precision: consensus, robust loss χ_t, its expectation d_t, outlier views.
struct TexelStatistic {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  double chi2 = 0.0, expected = 0.0;
  int outliers = 0;
};
TexelStatistic ReferenceTexelStatistic(const std::vector<ViewSample>& views, const LikelihoodModel& model,
                                       const PhotometricCorrection& photometric);

// How the colour a camera sees at a texel is read from its pyramid.
enum class ColourSampling {
  // Bilinear at the evaluation level l (pixel centres at +0.5, clamped to the edge).
  LevelBilinear,
  // Prefiltered: where a texel covers more than a pixel of level l, the colour comes from
  // the pyramid level that averages them. λ = l + max(0, ½·log₂ footprint) (footprint as in
  // the angle weight, in level-l pixels), clamped to the pyramid's last level; the colour
  // is the linear blend of bilinear samples at levels ⌊λ⌋ and ⌊λ⌋+1 by the fraction of λ,
  // level k sampled at (u, v)·2^(l−k) (Pyramid.h's geometry). What a trilinear mip-mapped
  // GPU sampler with an explicit LOD computes.
  Prefiltered,
};

// Every camera's image pyramid, in the order of scene.cameras: its photograph as the
// likelihoods load it (LoadCameraPhoto: undistorted when the camera has a lens) and
// BuildPyramid(image, levels). `validity`, when given, receives per camera the
// BuildValidityPyramid of its validity image (mask × lens border), or an empty pyramid for a
// camera whose every pixel counts.
std::vector<std::vector<Image>> LoadReferencePyramids(const Scene& scene, int levels,
                                                      std::vector<std::vector<Image>>* validity = nullptr);

// The reduced scalars of hypothesis `psi` at pyramid level `level`, as SurfaceLikelihood
// defines them. With ColourSampling::Prefiltered the pyramids need the levels λ can reach.
// `geometry` is BuildSceneGeometry(scene, scene.InitialValues(), atlas) (the
// atlas layout is shared with the GPU path); only options.model and options.weights are read,
// the atlas side comes from geometry.atlas.size. `texels`, when given, receives per-texel data.
// `validity` (from LoadReferencePyramids): a camera does not see a texel whose colour sample
// reads its validity pyramid, sampled the same way, below 0.999 (view_texture.frag's rule).
// `photometric`: the per-camera colour correction (null: the identity).
ReducedScalars ReferenceSurfaceScalars(const Scene& scene, const SceneGeometry& geometry,
                                       const std::vector<std::vector<Image>>& pyramids,
                                       const std::vector<double>& psi, int level,
                                       const SurfaceLikelihoodOptions& options,
                                       ReferenceTexels* texels = nullptr,
                                       ColourSampling sampling = ColourSampling::LevelBilinear,
                                       const std::vector<std::vector<Image>>* validity = nullptr,
                                       const PhotometricCorrection* photometric = nullptr);

// A triangle of the scene in world space: v0 and the edges v1 − v0, v2 − v0.
struct WorldTriangle {
  Eigen::Vector3d v0, e1, e2;
};
// Every triangle of `geometry` at the node matrices of a hypothesis, in index order.
std::vector<WorldTriangle> WorldTriangles(const SceneGeometry& geometry,
                                          const std::vector<Eigen::Matrix4d>& world_from_node);
// Möller–Trumbore: whether the segment o + t·d hits the triangle for t ∈ (10⁻⁴, 1 − 10⁻⁶),
// so that neither the surface the segment starts on nor the point it ends at counts.
bool SegmentHits(const WorldTriangle& tri, const Eigen::Vector3d& o, const Eigen::Vector3d& d);

// ---- Test scenes shared by the reference's own tests and the GPU comparison ----

// A scene-file camera entry (JSON object text) looking from `eye` at `target`, Z-up world,
// OpenCV axes, K = [[f, 0, cx], [0, f, cy], [0, 0, 1]].
std::string LookAtCameraJson(const std::string& name, const Eigen::Vector3d& eye,
                             const Eigen::Vector3d& target, int width, int height, double f,
                             double cx, double cy);

// The bundled box asset's textured box (parameters x, y, yaw, w, d, h) on a 4 m × 4 m
// textured ground, seen by 5 inline cameras of 160×120 on a ring of radius 1.9 m, 1.3–1.7 m
// high, with noise-free reference images synthesised by `vkrecon synth` at the truth (the
// asset's truth.json), which is also the scene's initial values (the atlas layout).
struct SynthBoxScene {
  std::unique_ptr<TempDir> dir;
  std::filesystem::path scene_file;
  Scene scene;
  std::vector<double> truth;
};
SynthBoxScene MakeSynthBoxScene(vk::Device& device);

// ψ with parameter `name` set to `value`.
std::vector<double> With(const Scene& scene, std::vector<double> psi, const std::string& name,
                         double value);

// Number of atlas texels whose centre lies on a triangle at `level` (independent of Ψ).
uint32_t SurfaceTexelCount(const SceneGeometry& geometry, int level);
// Those texels, row-major over the level's atlas: true where a centre lies on a triangle.
std::vector<bool> SurfaceTexels(const SceneGeometry& geometry, int level);

}  // namespace vkr::test
