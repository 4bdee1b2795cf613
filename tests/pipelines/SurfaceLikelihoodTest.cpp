// The GPU surface likelihood (SurfaceLikelihood) against the CPU reference
// (SurfaceReference.h) on the synthetic box scene, like Ceres's gradient checker: the same
// definitions computed two independent ways must agree within stated tolerances. Also the
// batching contract: a hypothesis evaluates bit-identically wherever it sits in a batch.
// The GPU reads a texel's colour from the mip level matching its footprint (trilinear), so
// the reference runs with ColourSampling::Prefiltered on a pyramid as deep as the GPU's.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "pipelines/passes/CompositePass.h"
#include "pipelines/passes/Projection.h"
#include "pipelines/passes/ViewCulling.h"
#include "tests/common/GpuTest.h"
#include "tests/pipelines/SurfaceReference.h"

namespace vkr::test {
namespace {

// Tolerances, from what the two paths legitimately do differently (the worst measured on
// this scene, lavapipe, in brackets):
//  * Counts: the GPU rasterises charts with the top-left rule where the reference takes every
//    texel centre on a triangle edge. Charts sit at whole level-0 texels, some at odd ones,
//    so at level ≥ 1 whole rows of texel centres lie exactly on chart edges and the GPU keeps
//    only the top/left ones (a box side's bottom row, interior to the ground, is the
//    reference's and not the GPU's) [0.05 % of surface texels at level 0, 1.6 % at level 1].
//    And the GPU tests visibility against a depth map (one depth per pixel, nearest sample,
//    slope-scaled tolerance) where the reference casts exact rays: texels along silhouettes
//    and contact lines change class. Both effects live on curves of the atlas, so they are a
//    few % of a 64² atlas and shrink on finer ones.
//  * dof follows the texels seen twice and their view counts [0.35 % level 0, 1.7 % level 1].
//  * sum_squares: at the truth of noise-free images S is small and dominated by the few
//    silhouette texels whose views differ between depth map and ray cast (their deviations
//    are the large, capped ones) [≤ 1.2 % on wrong hypotheses at level 0, 4.3 % at the truth;
//    5.3 % at level 1]. On top of that come colour errors (RGBA8 mips, 8-bit filter weights,
//    fp16 views, a float one-pass variance: +2 % of χ² where the views agree), which
//    PerTexelAndPerViewDataAgree checks separately and tightly.
constexpr double kCountTolerance = 0.02;       // of the surface texels at the level
constexpr double kDofTolerance = 0.03;         // relative
constexpr double kSumSquaresTolerance = 0.08;  // relative

// The GPU keeps the reference image as a mip chain down to a smallest side of 4 pixels
// (SurfaceLikelihood.cpp); the prefiltered reference needs the same pyramid levels.
int GpuMipCount(const Scene& scene) {
  int count = 1;
  while ((std::min(scene.cameras[0].width, scene.cameras[0].height) >> count) >= 4) ++count;
  return count;
}

// Triangles of node `node` with corners on both sides of camera `camera`'s near plane.
int NearPlaneCrossings(const Scene& scene, const SceneGeometry& geometry, const std::vector<double>& psi,
                       int camera, int node) {
  const Eigen::Matrix4d cam_from_node =
      scene.Cameras(psi)[size_t(camera)].cam_from_world * scene.WorldFromNode(psi)[size_t(node)];
  int crossings = 0;
  for (size_t t = 0; t + 2 < geometry.indices.size(); t += 3) {
    int in_front = 0;
    for (int k = 0; k < 3; ++k) {
      const GpuVertex& v = geometry.vertices[geometry.indices[t + k]];
      if (int(v.node) != node) break;
      in_front += (cam_from_node * Eigen::Vector4d(v.position[0], v.position[1], v.position[2], 1.0)).z() > kDefaultNear;
    }
    const GpuVertex& v = geometry.vertices[geometry.indices[t]];
    if (int(v.node) == node && in_front > 0 && in_front < 3) ++crossings;
  }
  return crossings;
}

class SurfaceLikelihoodVsReference : public GpuTest {
 protected:
  static const SynthBoxScene& Box() {
    static const SynthBoxScene box = MakeSynthBoxScene(device());
    return box;
  }
  static SurfaceLikelihoodOptions Options(ViewWeights weights) {
    SurfaceLikelihoodOptions o;
    o.model.sigma = 4.0;
    o.weights = weights;
    o.atlas = 128;
    o.levels = 2;
    o.max_batch = 4;
    return o;
  }
  // The hypotheses compared: truth, shifted, rotated, and a 5 m long bar that runs out of
  // several views and passes under camera 0, so its faces cross that camera's near plane.
  static std::vector<std::pair<std::string, std::vector<double>>> Hypotheses() {
    const SynthBoxScene& b = Box();
    const Scene& s = b.scene;
    return {{"truth", b.truth},
            {"shifted", With(s, b.truth, "x", b.truth[s.ParameterIndex("x")] + 0.2)},
            {"rotated", With(s, b.truth, "yaw", b.truth[s.ParameterIndex("yaw")] + 20.0)},
            {"long bar", With(s, b.truth, "w", 5.0)}};
  }
};

struct Worst {
  double count = 0, dof = 0, sum_squares = 0;
};

// The GPU's scalars of every hypothesis against the CPU reference's, at levels 0 and 1,
// for `scene` (the box's, or a variant of it) with `options`; the worst relative
// differences are folded into `worst`.
void ExpectScalarsAgree(const Scene& scene, const SurfaceLikelihoodOptions& options,
                        const std::vector<std::pair<std::string, std::vector<double>>>& hypotheses,
                        const std::vector<std::vector<Image>>& pyramids, Worst& worst) {
  std::vector<std::vector<double>> batch;
  for (const auto& h : hypotheses) batch.push_back(h.second);
  const SceneGeometry geometry = BuildSceneGeometry(scene, scene.InitialValues(), options.atlas, options.charts);
  SurfaceLikelihood likelihood(GpuTest::device(), scene, options);
  for (int level : {0, 1}) {
    likelihood.SetLevel(level);
    const std::vector<Evaluation> gpu = likelihood.Evaluate(batch);
    ASSERT_EQ(gpu.size(), batch.size());
    const double surface = SurfaceTexelCount(geometry, level);
    for (size_t k = 0; k < batch.size(); ++k) {
      const std::string what =
          std::string(ToString(options.weights)) + " level " + std::to_string(level) + " " + hypotheses[k].first;
      SCOPED_TRACE(what);
      const ReducedScalars ref = ReferenceSurfaceScalars(scene, geometry, pyramids, batch[k], level, options, nullptr,
                                                          ColourSampling::Prefiltered);
      const ReducedScalars& g = gpu[k].scalars;
      const double d_multi = std::abs(double(g.seen_multi) - ref.seen_multi) / surface;
      const double d_once = std::abs(double(g.seen_once) - ref.seen_once) / surface;
      const double d_none = std::abs(double(g.seen_none) - ref.seen_none) / surface;
      const double d_interior = std::abs(double(g.interior) - ref.interior) / surface;
      const double d_dof = std::abs(g.dof - ref.dof) / ref.dof;
      const double d_sum = std::abs(g.sum_squares - ref.sum_squares) / ref.sum_squares;
      std::printf("  %-28s gpu/ref multi %5u/%5u once %5u/%5u none %5u/%5u interior %5u/%5u"
                  " dof %7.0f/%7.0f (%.2f%%) S %.5g/%.5g (%.2f%%)\n",
                  what.c_str(), g.seen_multi, ref.seen_multi, g.seen_once, ref.seen_once, g.seen_none,
                  ref.seen_none, g.interior, ref.interior, g.dof, ref.dof, 100 * d_dof, g.sum_squares,
                  ref.sum_squares, 100 * d_sum);
      EXPECT_GT(ref.seen_multi, 0u);
      EXPECT_LE(d_multi, kCountTolerance);
      EXPECT_LE(d_once, kCountTolerance);
      EXPECT_LE(d_none, kCountTolerance);
      EXPECT_LE(d_interior, kCountTolerance);
      EXPECT_LE(d_dof, kDofTolerance);
      // Plus an absolute allowance: at the truth of noise-free images S is nearly zero and
      // the GPU's 8-bit colours (±0.5/255) add up to a quarter level's variance per dof.
      EXPECT_LE(std::abs(g.sum_squares - ref.sum_squares),
                kSumSquaresTolerance * ref.sum_squares + 0.25 * ref.dof / (255.0 * 255.0));
      worst.count = std::max({worst.count, d_multi, d_once, d_none, d_interior});
      worst.dof = std::max(worst.dof, d_dof);
      worst.sum_squares = std::max(worst.sum_squares, d_sum);
    }
  }
}

TEST_F(SurfaceLikelihoodVsReference, ScalarsAgreeWithTheCpuReference) {
  const SynthBoxScene& box = Box();
  const auto hypotheses = Hypotheses();
  const auto pyramids = LoadReferencePyramids(box.scene, GpuMipCount(box.scene));
  {
    const SceneGeometry geometry = BuildSceneGeometry(box.scene, box.scene.InitialValues(), 128, ChartSizing::Area);
    EXPECT_GT(NearPlaneCrossings(box.scene, geometry, hypotheses[3].second, 0, 1), 0);
    EXPECT_EQ(NearPlaneCrossings(box.scene, geometry, hypotheses[0].second, 0, 1), 0);
  }
  Worst worst;
  for (ViewWeights weights : {ViewWeights::Uniform, ViewWeights::Angle})
    ExpectScalarsAgree(box.scene, Options(weights), hypotheses, pyramids, worst);
  std::printf("  worst: counts %.3f%% of surface texels, dof %.3f%%, sum_squares %.3f%%\n", 100 * worst.count,
              100 * worst.dof, 100 * worst.sum_squares);
}

// likelihood.charts "pixels": the charts differ in scale, so each texel's footprint (and with
// it the LOD it is read at and its angle weight) must come from its own chart's texel area.
TEST_F(SurfaceLikelihoodVsReference, ChartsSizedByThePixelsAgreeToo) {
  const Scene scene = LoadScene(Box().scene_file, {{"likelihood.charts", "pixels"}});
  SurfaceLikelihoodOptions options = Options(ViewWeights::Angle);
  options.charts = LikelihoodSettingsOf(scene).charts;
  ASSERT_EQ(options.charts, ChartSizing::Pixels);
  // The faces the views barely see get charts a quarter as dense as the rest (AtlasFootprint.h):
  // at 128² those are a few texels, which halve at level 1 to where rasterisation's edge rules
  // and the reference's texel centres disagree on a share of them.
  options.atlas = 256;
  const SceneGeometry geometry = BuildSceneGeometry(scene, scene.InitialValues(), options.atlas, options.charts);
  double least = 1e30, most = 0.0;
  for (const Chart& c : geometry.atlas.charts) {
    least = std::min(least, c.texels_per_metre);
    most = std::max(most, c.texels_per_metre);
  }
  EXPECT_GT(most, 1.5 * least);  // otherwise this would test nothing the test above does not
  Worst worst;
  ExpectScalarsAgree(scene, options, Hypotheses(), LoadReferencePyramids(scene, GpuMipCount(scene)), worst);
}

// The same with what real photographs need switched on: a per-camera colour correction
// (Photometric.h) and a texture term of the noise large enough to matter (δ = 1.5 px).
TEST_F(SurfaceLikelihoodVsReference, WithAColourCorrectionAndTextureNoiseTheyStillAgree) {
  const SynthBoxScene& box = Box();
  SurfaceLikelihoodOptions options = Options(ViewWeights::Angle);
  options.model.position_sd = 1.5;
  PhotometricCorrection correction = PhotometricCorrection::Identity(int(box.scene.cameras.size()));
  for (int i = 0; i < correction.cameras(); ++i)
    for (int c = 0; c < 3; ++c) {
      correction.gain[size_t(i)][size_t(c)] = 0.85 + 0.07 * ((i + 2 * c) % 5);
      correction.offset[size_t(i)][size_t(c)] = 0.01 * ((3 * i + c) % 5 - 2);
    }
  const SceneGeometry geometry = BuildSceneGeometry(box.scene, box.scene.InitialValues(), options.atlas, options.charts);
  const auto pyramids = LoadReferencePyramids(box.scene, GpuMipCount(box.scene));
  SurfaceLikelihood likelihood(device(), box.scene, options);
  likelihood.SetPhotometric(correction);
  const auto hypotheses = Hypotheses();
  const std::vector<Evaluation> gpu = likelihood.Evaluate({hypotheses[0].second, hypotheses[1].second});
  for (size_t k = 0; k < gpu.size(); ++k) {
    SCOPED_TRACE(hypotheses[k].first);
    const ReducedScalars ref = ReferenceSurfaceScalars(box.scene, geometry, pyramids, hypotheses[k].second, 0, options,
                                                        nullptr, ColourSampling::Prefiltered, nullptr, &correction);
    const ReducedScalars& g = gpu[k].scalars;
    std::printf("  %-8s dof %.0f/%.0f S %.5g/%.5g outlier views %u/%u of %u/%u\n", hypotheses[k].first.c_str(), g.dof,
                ref.dof, g.sum_squares, ref.sum_squares, g.outlier_views, ref.outlier_views, g.views, ref.views);
    EXPECT_NEAR(g.dof, ref.dof, kDofTolerance * ref.dof);
    EXPECT_LE(std::abs(g.sum_squares - ref.sum_squares),
              kSumSquaresTolerance * ref.sum_squares + 0.25 * ref.dof / (255.0 * 255.0));
    EXPECT_NEAR(double(g.views), double(ref.views), 0.02 * ref.views);
    EXPECT_NEAR(double(g.outlier_views), double(ref.outlier_views), 0.01 * ref.views);
  }
  // The correction matters: without it the same hypotheses score differently.
  likelihood.SetPhotometric(PhotometricCorrection::Identity(correction.cameras()));
  EXPECT_LT(likelihood.Evaluate({hypotheses[0].second})[0].scalars.sum_squares, 0.5 * gpu[0].scalars.sum_squares);
}

// Texel by texel and view by view: the dump's view textures (rgb = colour, a = weight),
// deviation image (r = capped s_t/σ², b = interior, a = on surface) against the reference's.
// This separates the three things the scalars mix: which texels are on the surface and
// interior, which cameras see them, and what they see there.
TEST_F(SurfaceLikelihoodVsReference, PerTexelAndPerViewDataAgree) {
  const SynthBoxScene& box = Box();
  const SurfaceLikelihoodOptions options = Options(ViewWeights::Angle);
  const SceneGeometry geometry = BuildSceneGeometry(box.scene, box.scene.InitialValues(), options.atlas, options.charts);
  const auto pyramids = LoadReferencePyramids(box.scene, GpuMipCount(box.scene));
  SurfaceLikelihood likelihood(device(), box.scene, options);
  const auto hypotheses = Hypotheses();
  for (int level : {0, 1})
    for (size_t h : {size_t(0), size_t(3)}) {
      const std::string what = "level " + std::to_string(level) + " " + hypotheses[h].first;
      SCOPED_TRACE(what);
      likelihood.SetLevel(level);
      const SurfaceDump dump = likelihood.EvaluateAndDump(hypotheses[h].second);
      ReferenceTexels ref;
      ReferenceSurfaceScalars(box.scene, geometry, pyramids, hypotheses[h].second, level, options, &ref,
                              ColourSampling::Prefiltered);
      ASSERT_EQ(dump.deviation.width, ref.side);
      ASSERT_EQ(dump.view_textures.size(), ref.view_textures.size());
      int surface = 0, surface_diff = 0, interior_diff = 0;
      int pairs = 0, pairs_diff = 0, both = 0;
      double max_dw = 0, sum_dw = 0, max_dc = 0, sum_dc = 0, chi2_gpu = 0, chi2_ref = 0;
      for (int j = 0; j < ref.side; ++j)
        for (int i = 0; i < ref.side; ++i) {
          const size_t t = size_t(j) * ref.side + i;
          const float* dev = dump.deviation.At(i, j);
          const bool ref_surface = ref.state[t] != TexelState::OffSurface;
          surface += ref_surface;
          if (ref_surface != (dev[3] > 0.5f)) ++surface_diff;
          if (!ref_surface || dev[3] < 0.5f) continue;
          if ((dev[2] > 0.5f) != (ref.state[t] == TexelState::Interior)) ++interior_diff;
          if (ref.state[t] != TexelState::Exterior || dev[2] > 0.5f) continue;
          bool same_views = true;
          for (size_t c = 0; c < ref.view_textures.size(); ++c) {
            const float* r = ref.view_textures[c].At(i, j);
            const float* g = dump.view_textures[c].At(i, j);
            if (r[3] == 0.0f && g[3] == 0.0f) continue;
            ++pairs;
            if ((r[3] > 0.0f) != (g[3] > 0.0f)) {
              ++pairs_diff;
              same_views = false;
              continue;
            }
            ++both;
            max_dw = std::max(max_dw, double(std::abs(r[3] - g[3])));
            sum_dw += std::abs(r[3] - g[3]);
            for (int k = 0; k < 3; ++k) {
              max_dc = std::max(max_dc, 255.0 * std::abs(r[k] - g[k]));
              sum_dc += 255.0 * std::abs(r[k] - g[k]) / 3.0;
            }
          }
          if (same_views && ref.views[t] >= 2) {
            chi2_gpu += dev[0];
            chi2_ref += ref.deviation[t];
          }
        }
      std::printf("  %-16s surface %d (differ %d, interior differ %d); views %d (differ %d); "
                  "max |dw| %.2g, |dc| max %.2f/255 mean %.3f/255; chi2 where views agree %.1f/%.1f\n",
                  what.c_str(), surface, surface_diff, interior_diff, pairs, pairs_diff, max_dw, max_dc,
                  sum_dc / both, chi2_gpu, chi2_ref);
      // Level 0: no texel centre lies on a chart edge, so both rasterisations agree. Level
      // ≥ 1: whole edge rows tie, which the GPU's top-left rule halves (see kCountTolerance).
      EXPECT_LE(surface_diff, (level == 0 ? 0.001 : 0.03) * surface);
      EXPECT_LE(interior_diff, 0.005 * surface);
      // Shadow map vs ray cast: disagreements only along silhouettes and contact lines
      // [0.65 % of (texel, camera) pairs at level 0, 1.4 % at level 1].
      EXPECT_LE(pairs_diff, 0.02 * pairs);
      // Weights are stored as fp16 (steps of 2^-11 below 1) and computed in float from
      // interpolated positions [max 0.002, mean 1e-4].
      EXPECT_LE(max_dw, 0.01);
      EXPECT_LE(sum_dw / std::max(both, 1), 0.001);
      // RGBA8 mips of the float pyramid (±0.5/255 each), 8-bit filter weights, 8-bit storage
      // of the view colours [max 1.7/255, mean 0.35/255].
      EXPECT_LE(max_dc, 3.0);
      EXPECT_LE(sum_dc / both, 0.6);
      // Where both see the same views, the deviations agree up to those colour errors,
      // which add variance: at the noise-free truth (χ² per dof ≈ 0.1) they are a large part
      // of it, the more where a sample averages many pixels and so carries little noise
      // [GPU +18 % at the truth, +7 % at level 1, +1.6 % on the long bar].
      EXPECT_NEAR(chi2_gpu, chi2_ref, 0.25 * chi2_ref);
    }
}

TEST_F(SurfaceLikelihoodVsReference, AHypothesisEvaluatesIdenticallyWhereverItSitsInABatch) {
  const auto hypotheses = Hypotheses();
  const std::vector<double>& a = hypotheses[1].second;
  const std::vector<double>& b = hypotheses[2].second;
  SurfaceLikelihood likelihood(device(), Box().scene, Options(ViewWeights::Angle));
  for (int level : {0, 1}) {
    SCOPED_TRACE("level " + std::to_string(level));
    likelihood.SetLevel(level);
    const std::vector<Evaluation> batch = likelihood.Evaluate({a, b, a});
    const Evaluation single_a = likelihood.Evaluate({a})[0];
    const Evaluation single_b = likelihood.Evaluate({b})[0];
    auto same = [](const Evaluation& x, const Evaluation& y) {
      const ReducedScalars &p = x.scalars, &q = y.scalars;
      return p.sum_squares == q.sum_squares && p.dof == q.dof && p.seen_multi == q.seen_multi &&
             p.seen_once == q.seen_once && p.seen_none == q.seen_none && p.interior == q.interior &&
             x.log_likelihood == y.log_likelihood && x.log_occlusion_prior == y.log_occlusion_prior;
    };
    EXPECT_TRUE(same(batch[0], batch[2]));
    EXPECT_TRUE(same(batch[0], single_a));
    EXPECT_TRUE(same(batch[1], single_b));
    EXPECT_FALSE(same(batch[0], batch[1]));
  }
}

// Host-side culling (ViewCulling.h) only moves texels the shader would reject anyway to a
// pipeline that writes the same weight 0: every scalar must come out the same to the bit, on
// hypotheses where whole faces turn away, leave views, and cross a camera's near plane, and
// where the ground is drawn in parts.
TEST_F(SurfaceLikelihoodVsReference, CullingWhatACameraCannotSeeChangesNothing) {
  SurfaceLikelihoodOptions culled = Options(ViewWeights::Angle), shaded = culled;
  shaded.cull_views = false;
  SurfaceLikelihood with(device(), Box().scene, culled), without(device(), Box().scene, shaded);
  std::vector<std::vector<double>> batch;
  for (const auto& [name, psi] : Hypotheses()) batch.push_back(psi);
  for (int level : {0, 1}) {
    SCOPED_TRACE("level " + std::to_string(level));
    with.SetLevel(level);
    without.SetLevel(level);
    const std::vector<Evaluation> a = with.Evaluate(batch), b = without.Evaluate(batch);
    for (size_t k = 0; k < batch.size(); ++k) {
      SCOPED_TRACE(Hypotheses()[k].first);
      EXPECT_EQ(a[k].scalars.sum_squares, b[k].scalars.sum_squares);
      EXPECT_EQ(a[k].scalars.dof, b[k].scalars.dof);
      EXPECT_EQ(a[k].scalars.seen_multi, b[k].scalars.seen_multi);
      EXPECT_EQ(a[k].scalars.seen_once, b[k].scalars.seen_once);
      EXPECT_EQ(a[k].scalars.seen_none, b[k].scalars.seen_none);
      EXPECT_EQ(a[k].log_likelihood, b[k].log_likelihood);
    }
  }
  // And it culls: at the truth every camera skips some of the scene (the box's far sides,
  // ground outside its view), or the comparison above proved nothing.
  const ViewCulling culling(with.geometry());
  const Scene& scene = Box().scene;
  int cameras_in_parts = 0;
  const std::vector<Camera> cameras = scene.Cameras(Box().truth);
  for (size_t i = 0; i < cameras.size(); ++i) {
    const ViewDraws draws = culling.Classify(scene.WorldFromNode(Box().truth), ClipFromWorld(cameras[i]),
                                             cameras[i].Centre(), kDefaultNear);
    uint32_t unseen = 0, shaded_indices = 0, partial = 0;
    for (const IndexRun& r : draws.unseen) unseen += r.count;
    for (const IndexRun& r : draws.shaded) shaded_indices += r.count;
    for (const PartialRun& r : draws.partial) partial += r.indices.count;
    EXPECT_GT(unseen, 0u) << "camera " << i;
    EXPECT_GT(shaded_indices, 0u) << "camera " << i;
    EXPECT_EQ(unseen + shaded_indices + partial, uint32_t(with.geometry().indices.size())) << "camera " << i;
    cameras_in_parts += draws.partial.empty() ? 0 : 1;
  }
  EXPECT_GT(cameras_in_parts, 0) << "no camera drew the ground in parts: the comparison proved nothing of it";
}

// The composite visits only the workgroup tiles that touch a chart: every texel whose centre
// lies on a triangle must be in one, at every level, and tiles off the charts are skipped.
TEST_F(SurfaceLikelihoodVsReference, TheCompositeTilesCoverEverySurfaceTexel) {
  const SceneGeometry geometry = BuildSceneGeometry(Box().scene, Box().truth, 128, ChartSizing::Area);
  for (uint32_t lanes : {4u, 8u, 16u}) {
    for (int level : {0, 1, 2}) {
      SCOPED_TRACE("lanes " + std::to_string(lanes) + ", level " + std::to_string(level));
      const int side = geometry.atlas.size >> level;
      const std::vector<uint32_t> tiles = CompositePass::ChartTiles(geometry.atlas, level, lanes);
      std::vector<bool> visited(size_t(side) * side, false);
      for (size_t k = 0; k + 1 < tiles.size(); k += 2) {
        if (k >= 2) EXPECT_LT(tiles[k - 1] * 1000 + tiles[k - 2], tiles[k + 1] * 1000 + tiles[k]) << "row-major";
        for (uint32_t r = 0; r < 16; ++r)
          for (uint32_t x = 0; x < lanes; ++x) {
            const uint32_t tx = tiles[k] * lanes + x, ty = tiles[k + 1] * 16 + r;
            if (tx < uint32_t(side) && ty < uint32_t(side)) visited[size_t(ty) * side + tx] = true;
          }
      }
      const std::vector<bool> surface = SurfaceTexels(geometry, level);
      int missed = 0, surface_count = 0;
      for (size_t i = 0; i < surface.size(); ++i) {
        surface_count += surface[i];
        missed += surface[i] && !visited[i];
      }
      EXPECT_GT(surface_count, 0);
      EXPECT_EQ(missed, 0);
      // On a 128² atlas the charts leave whole tiles free at level 0 (coarser, they touch all).
      if (level == 0 && lanes <= 8)
        EXPECT_LT(std::count(visited.begin(), visited.end(), true), std::ptrdiff_t(visited.size()));
    }
  }
}

// Per-slot images (SlotImages::PerSlot) let a GPU overlap the hypotheses of a batch; they
// must not change what a hypothesis evaluates to: the same scalars, to the bit, as with the
// images all slots share, on a batch with a repeated hypothesis, at two levels, and after a
// dump (which clears slot 0's layers).
TEST_F(SurfaceLikelihoodVsReference, PerSlotImagesEvaluateAsSharedOnesDo) {
  SurfaceLikelihoodOptions shared_options = Options(ViewWeights::Angle), per_slot_options = shared_options;
  shared_options.slot_images = SlotImages::Shared;
  per_slot_options.slot_images = SlotImages::PerSlot;
  SurfaceLikelihood shared(device(), Box().scene, shared_options), per_slot(device(), Box().scene, per_slot_options);
  EXPECT_EQ(per_slot.options().slot_images, SlotImages::PerSlot);
  const auto hypotheses = Hypotheses();
  const std::vector<std::vector<double>> batch = {hypotheses[1].second, hypotheses[3].second, hypotheses[0].second,
                                                  hypotheses[1].second};
  for (int round = 0; round < 2; ++round) {
    for (int level : {0, 1}) {
      SCOPED_TRACE("round " + std::to_string(round) + ", level " + std::to_string(level));
      shared.SetLevel(level);
      per_slot.SetLevel(level);
      const std::vector<Evaluation> a = shared.Evaluate(batch), b = per_slot.Evaluate(batch);
      for (size_t k = 0; k < batch.size(); ++k) {
        EXPECT_EQ(a[k].scalars.sum_squares, b[k].scalars.sum_squares) << k;
        EXPECT_EQ(a[k].scalars.dof, b[k].scalars.dof) << k;
        EXPECT_EQ(a[k].scalars.seen_multi, b[k].scalars.seen_multi) << k;
        EXPECT_EQ(a[k].scalars.seen_none, b[k].scalars.seen_none) << k;
        EXPECT_EQ(a[k].log_likelihood, b[k].log_likelihood) << k;
      }
      EXPECT_EQ(b[0].log_likelihood, b[3].log_likelihood);
    }
    Evaluation dumped;
    per_slot.EvaluateAndDump(batch[2], &dumped);
    EXPECT_EQ(dumped.log_likelihood, shared.Evaluate({batch[2]})[0].log_likelihood);
  }
  // On this CPU device "auto" keeps one shared set: copies would cost memory for nothing.
  SurfaceLikelihoodOptions automatic = Options(ViewWeights::Angle);
  if (device().is_cpu())
    EXPECT_EQ(ResolveSlotImages(automatic, Box().scene, device()).slot_images, SlotImages::Shared);
}

}  // namespace
}  // namespace vkr::test
