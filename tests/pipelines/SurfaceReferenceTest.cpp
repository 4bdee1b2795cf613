// The CPU reference of the surface likelihood on its own (SurfaceReference.h): analytic
// counts of interior, occluded and back-facing texels in scenes simple enough to work out
// by hand, and photo-consistency on noise-free synthetic images of the box asset.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>

#include "engine/image/Pyramid.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"
#include "tests/pipelines/SurfaceReference.h"

namespace vkr::test {
namespace {

Scene LoadWithoutImages(const TempDir& dir, const std::string& json) {
  WriteText(dir / "scene.json", json);
  LoadOptions load;
  load.require_images = false;
  return LoadScene(dir / "scene.json", {}, load);
}

// Constant grey pyramids of the cameras' sizes.
std::vector<std::vector<Image>> GreyPyramids(const Scene& scene, int levels) {
  std::vector<std::vector<Image>> out;
  for (const CameraModel& c : scene.cameras) {
    Image image(c.width, c.height, 0.5f);
    out.push_back(BuildPyramid(image, levels));
  }
  return out;
}

// The node-frame normal of a chart's first vertex.
Eigen::Vector3f ChartNormal(const SceneGeometry& g, int chart) {
  for (const GpuVertex& v : g.vertices)
    if (int(v.face) == chart) return {v.normal[0], v.normal[1], v.normal[2]};
  return Eigen::Vector3f::Zero();
}

// Per chart: how many texels of each state, and the on-surface total.
struct ChartCounts {
  std::map<int, int> surface, interior, seen_none, seen_once;
};
ChartCounts CountByChart(const ReferenceTexels& t) {
  ChartCounts c;
  for (size_t i = 0; i < t.state.size(); ++i) {
    if (t.state[i] == TexelState::OffSurface) continue;
    const int chart = t.chart[i];
    ++c.surface[chart];
    if (t.state[i] == TexelState::Interior) ++c.interior[chart];
    else if (t.views[i] == 0) ++c.seen_none[chart];
    else if (t.views[i] == 1) ++c.seen_once[chart];
  }
  return c;
}

// A 0.6 m × 0.6 m × 0.4 m box on a 2 m × 2 m ground, one camera 3 m straight above.
constexpr const char* kBoxFromAbove = R"({
  "version": 1,
  "parameters": {"h": {"prior": {"uniform": [0.1, 1]}, "init": 0.4}},
  "nodes": [
    {"name": "ground", "primitive": "plane", "transforms": [{"scale": [2, 2, 1]}]},
    {"name": "box", "primitive": "box", "transforms": [{"scale": [0.6, 0.6, "h"]}]}
  ],
  "cameras": [{"name": "top", "image": "top.png", "width": 160, "height": 120,
               "K": [[150, 0, 80], [0, 150, 60], [0, 0, 1]],
               "R": [[1, 0, 0], [0, -1, 0], [0, 0, -1]], "t": [0, 0, 3]}]
})";

// Seen from straight above, the box hides the ground inside the central projection of its
// top face from the camera centre, minus its own footprint (which is interior); its sides
// face away; its top is seen; its bottom lies in the ground's half-space. All of it is
// fixed by geometry, so the counts follow from chart areas.
TEST(SurfaceReference, BoxSeenFromAboveHidesTheGroundInItsShadow) {
  TempDir dir;
  const Scene scene = LoadWithoutImages(dir, kBoxFromAbove);
  const std::vector<double> psi = scene.InitialValues();
  const SceneGeometry geometry = BuildSceneGeometry(scene, psi, 256, ChartSizing::Area);
  const auto pyramids = GreyPyramids(scene, 1);
  SurfaceLikelihoodOptions options;
  ReferenceTexels texels;
  const ReducedScalars r = ReferenceSurfaceScalars(scene, geometry, pyramids, psi, 0, options, &texels);
  ChartCounts c = CountByChart(texels);

  // Charts: 0 = ground; 1–4 = box sides, 5 = top, 6 = bottom (Primitives.cpp).
  ASSERT_EQ(geometry.atlas.charts.size(), 7u);
  const double ground = c.surface.at(0);
  // Ground area 4 m². The interior test's ε = 1e-3 widens the box's 0.6 m by 0.12 %.
  const double footprint = std::pow(0.6 * 1.002, 2.0);
  const double shadow = std::pow(0.6 * 3.0 / (3.0 - 0.4), 2.0);  // top face projected onto z = 0
  // Texel centres on a lattice against axis-aligned squares: each count may be off by up to
  // one row of texels along each boundary it has.
  const double per_metre = std::sqrt(ground / 4.0);
  const double footprint_rows = 4.0 * std::sqrt(footprint) * per_metre;
  const double shadow_rows = 4.0 * std::sqrt(shadow) * per_metre;
  EXPECT_NEAR(c.interior[0], ground * footprint / 4.0, footprint_rows);
  EXPECT_NEAR(c.seen_none[0], ground * (shadow - footprint) / 4.0, footprint_rows + shadow_rows);
  EXPECT_NEAR(c.seen_once[0], ground * (4.0 - shadow) / 4.0, shadow_rows);
  std::printf("  ground: %d texels, interior %d (%.1f), unseen %d (%.1f), seen %d (%.1f)\n", c.surface.at(0),
              c.interior[0], ground * footprint / 4.0, c.seen_none[0], ground * (shadow - footprint) / 4.0,
              c.seen_once[0], ground * (4.0 - shadow) / 4.0);
  for (int side = 1; side <= 4; ++side) {
    EXPECT_GT(c.surface.at(side), 100);
    EXPECT_EQ(c.seen_none[side], c.surface.at(side)) << "side " << side << " faces away from the camera";
  }
  EXPECT_EQ(ChartNormal(geometry, 5).z(), 1.0f);
  EXPECT_EQ(c.seen_once[5], c.surface.at(5)) << "the top is in full view";
  EXPECT_EQ(ChartNormal(geometry, 6).z(), -1.0f);
  EXPECT_EQ(c.interior[6], c.surface.at(6)) << "the bottom stands on the ground";

  // One camera: nothing is seen twice, so there is nothing to compare.
  EXPECT_EQ(r.seen_multi, 0u);
  EXPECT_EQ(r.dof, 0.0);
  EXPECT_EQ(r.sum_squares, 0.0);
  EXPECT_EQ(r.seen_multi + r.seen_once + r.seen_none + r.interior, SurfaceTexelCount(geometry, 0));
  EXPECT_EQ(SurfaceTexelCount(geometry, 0), uint32_t(texels.state.size()) -
            uint32_t(std::count(texels.state.begin(), texels.state.end(), TexelState::OffSurface)));
}

// Box with a prism roof, a cylinder, a ground: every kind of inside test. Three cameras.
constexpr const char* kPrimitives = R"({
  "version": 1,
  "parameters": {"x": {"prior": {"uniform": [-1, 0]}, "init": -0.5}},
  "nodes": [
    {"name": "ground", "primitive": "plane", "transforms": [{"scale": [3, 3, 1]}]},
    {"name": "box", "primitive": "box", "transforms": [{"translate": ["x", 0, 0]}, {"scale": [0.6, 0.6, 0.4]}]},
    {"name": "roof", "parent": "box", "primitive": "prism", "transforms": [{"translate": [0, 0, 1]}, {"scale": [1, 1, 0.5]}]},
    {"name": "drum", "primitive": "cylinder", "transforms": [{"translate": [0.6, 0.3, 0]}, {"scale": [0.4, 0.4, 0.5]}]}
  ],
  "cameras": [
    {"name": "a", "image": "a.png", "width": 160, "height": 120, "K": [[120, 0, 80], [0, 120, 60], [0, 0, 1]],
     "R": [[1, 0, 0], [0, -0.6, -0.8], [0, 0.8, -0.6]], "t": [0, 0, 3.2]},
    {"name": "b", "image": "b.png", "width": 160, "height": 120, "K": [[120, 0, 80], [0, 120, 60], [0, 0, 1]],
     "R": [[0, 1, 0], [0.6, 0, -0.8], [-0.8, 0, -0.6]], "t": [0, 0, 3.2]},
    {"name": "c", "image": "c.png", "width": 160, "height": 120, "K": [[120, 0, 80], [0, 120, 60], [0, 0, 1]],
     "R": [[-1, 0, 0], [0, 0.6, -0.8], [0, -0.8, -0.6]], "t": [0, 0, 3.2]}
  ]
})";

TEST(SurfaceReference, InteriorTexelsAreTheContactAreasOfEveryPrimitive) {
  TempDir dir;
  const Scene scene = LoadWithoutImages(dir, kPrimitives);
  const std::vector<double> psi = scene.InitialValues();
  const SceneGeometry geometry = BuildSceneGeometry(scene, psi, 256, ChartSizing::Area);
  const auto pyramids = GreyPyramids(scene, 2);
  SurfaceLikelihoodOptions options;
  ReferenceTexels texels;
  const ReducedScalars r = ReferenceSurfaceScalars(scene, geometry, pyramids, psi, 0, options, &texels);
  ChartCounts c = CountByChart(texels);

  // Charts whose faces lie wholly inside a neighbour: the box's bottom (on the ground) and
  // top (under the roof), the roof's base (on the box), the drum's bottom cap (on the ground).
  double whole = 0.0;
  int whole_charts = 0;
  for (size_t k = 0; k < geometry.atlas.charts.size(); ++k) {
    const Chart& chart = geometry.atlas.charts[k];
    const Eigen::Vector3f n = ChartNormal(geometry, int(k));
    const bool bottom = n.z() < -0.99f;
    const bool box_top = chart.node == 1 && n.z() > 0.99f;
    if (chart.node == 0 || !(bottom || box_top)) continue;
    EXPECT_EQ(c.interior[int(k)], c.surface.at(int(k))) << "chart " << k << " of node " << chart.node;
    whole += c.surface.at(int(k));
    ++whole_charts;
  }
  EXPECT_EQ(whole_charts, 4);
  // The ground (9 m²) is interior under the box and under the drum; the inside tests are
  // widened by ε = 1e-3 of each primitive's unit size, and the drum's test is a true circle.
  const double ground = c.surface.at(0);
  const double under = std::pow(0.6 * 1.002, 2.0) + M_PI * std::pow(0.4 * 0.501, 2.0);
  // Up to a row of texels along the outlines (2.4 m of box, 1.26 m of drum).
  const double outline_rows = (2.4 + M_PI * 0.4) * std::sqrt(ground / 9.0);
  EXPECT_NEAR(c.interior[0], ground * under / 9.0, outline_rows);
  // Nothing else is inside anything beyond a strip of texels at the contact edges.
  const double expected = whole + ground * under / 9.0;
  EXPECT_NEAR(double(r.interior), expected, 2.0 * outline_rows);
  std::printf("  interior %u (expected %.1f ± %.1f); multi %u once %u none %u\n", r.interior, expected,
              2.0 * outline_rows, r.seen_multi, r.seen_once, r.seen_none);

  // Every camera sees a constant grey: the seen texels agree perfectly.
  EXPECT_GT(r.seen_multi, r.seen_once);
  EXPECT_LT(r.sum_squares, 1e-20);
  double dof = 0.0;
  for (size_t i = 0; i < texels.state.size(); ++i)
    if (texels.state[i] == TexelState::Exterior && texels.views[i] >= 2) {
      // A constant image has no gradient: the weights are the geometric ones, each ≤ 1,
      // and d_t lies between 0 and 3(n_t − 1).
      EXPECT_GT(texels.dof[i], 0.0);
      EXPECT_LE(texels.dof[i], 3.0 * (texels.views[i] - 1) + 1e-12);
      dof += texels.dof[i];
    }
  EXPECT_NEAR(r.dof, dof, 1e-9 * dof);
  EXPECT_EQ(r.seen_multi + r.seen_once + r.seen_none + r.interior, SurfaceTexelCount(geometry, 0));

  // Level 1 halves the atlas side: a quarter of the texels.
  // Charts sit at whole level-0 texels, some at odd ones: then level-1 texel centres fall
  // exactly on chart edges, and the inclusive inside test takes the whole edge row (a box
  // side's bottom row, on the ground, becomes interior). So only the ground, whose chart is
  // at an even offset, keeps its interior share exactly.
  ReferenceTexels texels1;
  const ReducedScalars r1 = ReferenceSurfaceScalars(scene, geometry, pyramids, psi, 1, options, &texels1);
  ChartCounts c1 = CountByChart(texels1);
  const double total0 = SurfaceTexelCount(geometry, 0), total1 = SurfaceTexelCount(geometry, 1);
  EXPECT_EQ(r1.seen_multi + r1.seen_once + r1.seen_none + r1.interior, uint32_t(total1));
  EXPECT_NEAR(total1, total0 / 4.0, 0.03 * total0 / 4.0);
  EXPECT_EQ(c1.surface.at(0), c.surface.at(0) / 4);
  EXPECT_NEAR(c1.interior[0], c.interior[0] / 4.0, outline_rows / 2.0);
  EXPECT_LT(r1.sum_squares, 1e-20);
}

// The box asset at its truth, on noise-free synthetic images (synthesised once per binary).
class SurfaceReferenceSynth : public GpuTest {
 protected:
  static const SynthBoxScene& Box() {
    static const SynthBoxScene box = MakeSynthBoxScene(device());
    return box;
  }
  static const SceneGeometry& Geometry() {
    static const SceneGeometry g = BuildSceneGeometry(Box().scene, Box().scene.InitialValues(), 128, ChartSizing::Area);
    return g;
  }
  static const std::vector<std::vector<Image>>& Pyramids() {
    static const auto p = LoadReferencePyramids(Box().scene, 2);
    return p;
  }
};

double ChiSquarePerDof(const ReducedScalars& r, double sigma) {
  const double s = sigma / 255.0;
  return r.sum_squares / (s * s) / r.dof;
}

TEST_F(SurfaceReferenceSynth, TruthIsPhotoConsistentAndAShiftedBoxIsNot) {
  const SynthBoxScene& box = Box();
  SurfaceLikelihoodOptions options;
  options.model.sigma = 2.0;
  options.model.outlier_chi2 = 1e9;  // see the raw deviations
  const std::vector<double> shifted = With(box.scene, box.truth, "x", box.truth[0] + 0.2);
  for (ViewWeights weights : {ViewWeights::Uniform, ViewWeights::Angle})
    for (int level : {0, 1}) {
      SCOPED_TRACE(std::string(weights == ViewWeights::Angle ? "angle" : "uniform") + " level " + std::to_string(level));
      options.weights = weights;
      const ReducedScalars t = ReferenceSurfaceScalars(box.scene, Geometry(), Pyramids(), box.truth, level, options);
      const ReducedScalars s = ReferenceSurfaceScalars(box.scene, Geometry(), Pyramids(), shifted, level, options);
      const double chi_t = ChiSquarePerDof(t, 2.0), chi_s = ChiSquarePerDof(s, 2.0);
      std::printf("  %s level %d: chi2/dof truth %.3f shifted %.3f; truth multi %u once %u none %u interior %u\n",
                  weights == ViewWeights::Angle ? "angle" : "uniform", level, chi_t, chi_s, t.seen_multi,
                  t.seen_once, t.seen_none, t.interior);
      EXPECT_GT(t.dof, 0.0);
      EXPECT_GT(chi_s, 5.0 * chi_t);
      EXPECT_GT(t.interior, 0u) << "the box's underside lies on the ground";
      EXPECT_GT(t.seen_multi, 2 * (t.seen_once + t.seen_none));
      EXPECT_EQ(t.seen_multi + t.seen_once + t.seen_none + t.interior, SurfaceTexelCount(Geometry(), level));
      EXPECT_EQ(s.seen_multi + s.seen_once + s.seen_none + s.interior, SurfaceTexelCount(Geometry(), level));
    }
}

TEST_F(SurfaceReferenceSynth, ScalarsAreTheSumsOfThePerTexelData) {
  const SynthBoxScene& box = Box();
  SurfaceLikelihoodOptions options;
  options.model.sigma = 2.0;
  options.model.outlier_chi2 = 12.0;
  const double s2 = std::pow(2.0 / 255.0, 2.0);
  ReferenceTexels texels;
  const ReducedScalars r = ReferenceSurfaceScalars(box.scene, Geometry(), Pyramids(), box.truth, 0, options, &texels);
  ReducedScalars sum;
  for (size_t i = 0; i < texels.state.size(); ++i) {
    if (texels.state[i] == TexelState::OffSurface) continue;
    if (texels.state[i] == TexelState::Interior) { ++sum.interior; continue; }
    const int n = texels.views[i];
    if (n == 0) ++sum.seen_none;
    else if (n == 1) ++sum.seen_once;
    else {
      ++sum.seen_multi;
      sum.dof += texels.dof[i];
      sum.sum_squares += texels.deviation[i] * s2;
      sum.views += uint32_t(n);
      sum.outlier_views += texels.outliers[i];
    }
  }
  EXPECT_EQ(r.seen_multi, sum.seen_multi);
  EXPECT_EQ(r.seen_once, sum.seen_once);
  EXPECT_EQ(r.seen_none, sum.seen_none);
  EXPECT_EQ(r.interior, sum.interior);
  EXPECT_NEAR(r.dof, sum.dof, 1e-9 * sum.dof);
  EXPECT_NEAR(r.sum_squares, sum.sum_squares, 1e-12 * sum.sum_squares);
  EXPECT_EQ(r.views, sum.views);
  EXPECT_EQ(r.outlier_views, sum.outlier_views);
  // The robust loss saturates somewhere (anti-aliased silhouettes), but on few views.
  const ReducedScalars quadratic = [&] {
    SurfaceLikelihoodOptions o = options;
    o.model.outlier_chi2 = 1e9;
    return ReferenceSurfaceScalars(box.scene, Geometry(), Pyramids(), box.truth, 0, o);
  }();
  EXPECT_LT(r.sum_squares, quadratic.sum_squares);
  EXPECT_GT(r.outlier_views, 0u);
  EXPECT_LT(r.outlier_views, r.views / 20);
}

// The statistic of one texel, against what the model promises (Evaluation.h).
TEST(ReferenceTexelStatistic, ItsExpectationIsWhatNoiseAloneGives) {
  // Monte Carlo over texels whose views differ only by noise of the model's variance: the
  // mean loss equals the mean expectation, for unequal weights and textures too.
  LikelihoodModel model;
  model.sigma = 6.0;
  model.position_sd = 0.8;
  const PhotometricCorrection identity = PhotometricCorrection::Identity(5);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> unit(0.0, 1.0);
  for (const int n : {2, 3, 5}) {
    double chi2 = 0.0, expected = 0.0;
    const int trials = 20000;
    for (int t = 0; t < trials; ++t) {
      std::vector<ViewSample> views;
      for (int i = 0; i < n; ++i) {
        ViewSample v;
        v.camera = i;
        v.weight = 0.3 + 0.7 * (i + 1) / n;
        v.texture = 0.04 * i;  // up to 4 %/pixel: the texture term matters
        v.mass = 1.0 + 3.0 * i;  // and samples that average several pixels
        const double sd = std::sqrt(std::pow(model.sigma / 255.0, 2) / v.mass + std::pow(model.position_sd * v.texture, 2));
        for (int k = 0; k < 3; ++k) v.colour[k] = 0.5 + sd * unit(rng);
        views.push_back(v);
      }
      const TexelStatistic s = ReferenceTexelStatistic(views, model, identity);
      chi2 += s.chi2 / trials;
      expected += s.expected / trials;
    }
    std::printf("  %d views: mean loss / mean expectation %.4f\n", n, chi2 / expected);
    EXPECT_NEAR(chi2 / expected, 1.0, 0.02) << n << " views";
  }
}

TEST(ReferenceTexelStatistic, AnOutlierViewStopsPullingTheConsensusAndItsLossSaturates) {
  LikelihoodModel model;
  model.sigma = 4.0;
  const PhotometricCorrection identity = PhotometricCorrection::Identity(4);
  std::vector<ViewSample> views;
  for (int i = 0; i < 4; ++i) views.push_back({Eigen::Vector3d(0.40, 0.50, 0.60), 1.0, 0.0, i});
  views[3].colour = Eigen::Vector3d(0.9, 0.1, 0.2);  // something the scene lacks, in one photo
  const TexelStatistic s = ReferenceTexelStatistic(views, model, identity);
  EXPECT_NEAR(s.mean[0], 0.40, 1e-3) << "the three agreeing views decide the consensus";
  EXPECT_EQ(s.outliers, 1);
  EXPECT_NEAR(s.chi2, model.outlier_chi2, 0.01 * model.outlier_chi2) << "one saturated view, three exact ones";
  // A plain mean would have moved an eighth of the way, and a quadratic loss would be huge.
  LikelihoodModel quadratic = model;
  quadratic.outlier_chi2 = 1e12;
  EXPECT_GT(ReferenceTexelStatistic(views, quadratic, identity).chi2, 1000.0);
}

TEST(ReferenceTexelStatistic, ThePhotometricCorrectionMakesDifferentExposuresAgree) {
  LikelihoodModel model;
  model.sigma = 2.0;
  PhotometricCorrection correction = PhotometricCorrection::Identity(2);
  const Eigen::Vector3d albedo(0.3, 0.4, 0.5);
  std::vector<ViewSample> views = {{albedo, 1.0, 0.0, 0}, {1.3 * albedo + Eigen::Vector3d::Constant(0.05), 1.0, 0.0, 1}};
  EXPECT_GT(ReferenceTexelStatistic(views, model, correction).chi2, 10.0);
  correction.gain[1] = {1 / 1.3, 1 / 1.3, 1 / 1.3};
  correction.offset[1] = {-0.05 / 1.3, -0.05 / 1.3, -0.05 / 1.3};
  EXPECT_LT(ReferenceTexelStatistic(views, model, correction).chi2, 1e-9);
}

}  // namespace
}  // namespace vkr::test
