// The surface likelihood's edge term: its statistic (pipelines/model/EdgeEvidence.h), the
// model's edges (pipelines/passes/EdgePass.h), and the GPU pass against the CPU reference
// (tests/pipelines/EdgeReference.h) on the synthetic box.

#include <gtest/gtest.h>

#include <cmath>

#include "engine/geometry/Mesh.h"
#include "engine/image/Pyramid.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"
#include "pipelines/model/EdgeEvidence.h"
#include "pipelines/passes/EdgePass.h"
#include "tests/common/GpuTest.h"
#include "tests/pipelines/EdgeReference.h"
#include "tests/pipelines/SurfaceReference.h"

namespace vkr {
namespace {

TEST(EdgeEvidence, OneSampleCanNeitherVetoNorCarryAHypothesis) {
  const double v = 2.0 * std::pow(4.0 / 255.0, 2), clutter = 0.05, hidden = 0.2;
  // No difference at all: the edge is one of the hidden ones, log η.
  EXPECT_NEAR(EdgeLogRatio(Eigen::Vector3d::Zero(), v, clutter, hidden), std::log(hidden), 1e-3);
  // A difference no noise makes: log((1 − η + ηε)/ε).
  EXPECT_NEAR(EdgeLogRatio(Eigen::Vector3d(0.5, 0.5, 0.5), v, clutter, hidden),
              std::log((1.0 - hidden + hidden * clutter) / clutter), 1e-9);
  double previous = -1e9;
  for (double d = 0.0; d <= 0.3; d += 0.01) {
    const double r = EdgeLogRatio(Eigen::Vector3d(d, 0.0, 0.0), v, clutter, hidden);
    EXPECT_GE(r, previous - 1e-12) << "a larger difference is more of an edge, at " << d;
    previous = r;
  }
  // A tiny variance neither overflows nor underflows: any difference beyond it is a contrast,
  // and none is η's.
  EXPECT_NEAR(EdgeLogRatio(Eigen::Vector3d(1e-4, 0, 0), 1e-12, clutter, hidden),
              std::log((1.0 - hidden + hidden * clutter) / clutter), 1e-9);
  EXPECT_NEAR(EdgeLogRatio(Eigen::Vector3d::Zero(), 1e-12, clutter, hidden), std::log(hidden), 1e-9);
}

TEST(EdgeEvidence, NoiseAloneRarelyPassesForAContrast) {
  // Δ ~ N(0, v) per channel: |Δ|²/v is χ² with 3 degrees of freedom; its tail beyond the
  // threshold is the share of noise-only pairs counted as contrasts.
  for (const double sigma : {2.0, 8.0, 32.0}) {
    const double v = 2.0 * std::pow(sigma / 255.0, 2);
    const double x = ContrastThreshold(v) / v;
    const double tail = std::erfc(std::sqrt(x / 2.0)) + std::sqrt(2.0 * x / M_PI) * std::exp(-x / 2.0);  // χ²₃
    EXPECT_LE(tail, 0.01) << "σ " << sigma;
  }
}

TEST(EdgeEvidence, TheClutterShareCountsPairsNoiseCannotExplain) {
  // 20 × 10, black left of x = 10, white right: 10 of 370 neighbouring pairs straddle the step.
  Image image(20, 10, 0.0f);
  for (int y = 0; y < 10; ++y)
    for (int x = 10; x < 20; ++x)
      for (int c = 0; c < 3; ++c) image.At(x, y)[c] = 1.0f;
  const PairContrasts pairs(image, Image());
  EXPECT_EQ(pairs.size(), 370u);
  const double v = 2.0 * std::pow(8.0 / 255.0, 2);
  EdgeModel model;
  EXPECT_NEAR(ClutterShare(pairs, v, model), 10.0 / 370.0, 1e-9);
  // Pairs outside the validity do not count: the right half masked leaves no step.
  Image validity(20, 10, 1.0f);
  for (int y = 0; y < 10; ++y)
    for (int x = 10; x < 20; ++x) validity.At(x, y)[0] = 0.0f;
  EXPECT_EQ(ClutterShare(PairContrasts(image, validity), v, model), model.min_clutter);
  // A picture of nothing but steps is capped: edges still count a little.
  Image checker(20, 10, 0.0f);
  for (int y = 0; y < 10; ++y)
    for (int x = (y % 2); x < 20; x += 2)
      for (int c = 0; c < 3; ++c) checker.At(x, y)[c] = 1.0f;
  EXPECT_EQ(ClutterShare(PairContrasts(checker, Image()), v, model), model.max_clutter);
}

// One node's primitive flattened as SceneGeometry flattens it.
SceneGeometry Flatten(PrimitiveKind kind) {
  const Mesh mesh = MakePrimitive(kind);
  SceneGeometry g;
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    GpuVertex gv{};
    for (int k = 0; k < 3; ++k) gv.position[k] = mesh.positions[v][k];
    g.vertices.push_back(gv);
  }
  g.indices = mesh.indices;
  return g;
}

TEST(ModelEdges, BoxPrismAndPlaneHaveTheirEdgesOutwardOriented) {
  struct Case {
    PrimitiveKind kind;
    size_t edges, borders;
  };
  for (const Case& c : {Case{PrimitiveKind::Box, 12, 0}, Case{PrimitiveKind::Prism, 9, 0}, Case{PrimitiveKind::Plane, 4, 4}}) {
    const std::vector<ModelEdge> edges = FindModelEdges(Flatten(c.kind));
    EXPECT_EQ(edges.size(), c.edges) << int(c.kind);
    size_t borders = 0;
    const Eigen::Vector3f centre(0.0f, 0.0f, c.kind == PrimitiveKind::Plane ? -1.0f : 0.3f);
    for (const ModelEdge& e : edges) {
      borders += e.sign1 == 0.0f;
      // Each face's normal points away from a point inside the solid (below the plane).
      const Eigen::Vector3f n0 = e.sign0 * (e.b - e.a).cross(e.c0 - e.a);
      EXPECT_GT(n0.dot(e.a - centre), 0.0f);
      if (e.sign1 != 0.0f) {
        const Eigen::Vector3f n1 = e.sign1 * (e.b - e.a).cross(e.c1 - e.a);
        EXPECT_GT(n1.dot(e.a - centre), 0.0f);
      }
    }
    EXPECT_EQ(borders, c.borders) << int(c.kind);
  }
}

// The box asset at its truth, on noise-free synthetic images.
class EdgeTerm : public test::GpuTest {
 protected:
  static const test::SynthBoxScene& Box() {
    static const test::SynthBoxScene box = test::MakeSynthBoxScene(device());
    return box;
  }
  static SurfaceLikelihoodOptions Options(bool edges) {
    SurfaceLikelihoodOptions options;
    options.model.sigma = 4.0;
    options.atlas = 256;
    options.levels = 2;
    options.max_batch = 4;
    options.edges = edges;
    return options;
  }
};

TEST_F(EdgeTerm, TheGpuPassMatchesTheCpuReference) {
  const test::SynthBoxScene& box = Box();
  SurfaceLikelihood likelihood(device(), box.scene, Options(true));
  const auto pyramids = test::LoadReferencePyramids(box.scene, 2);
  const std::vector<std::vector<double>> batch = {box.truth, test::With(box.scene, box.truth, "x", box.truth[0] + 0.04),
                                                  test::With(box.scene, box.truth, "yaw", box.truth[2] + 6.0)};
  for (int level = 0; level < 2; ++level) {
    likelihood.SetLevel(level);
    const std::vector<Evaluation> gpu = likelihood.Evaluate(batch);
    for (size_t k = 0; k < batch.size(); ++k) {
      const test::EdgeSums cpu =
          test::ReferenceEdgeSums(box.scene, likelihood.geometry(), pyramids, batch[k], level, likelihood.options());
      std::printf("  level %d, hypothesis %zu: GPU %.2f over %.1f px, CPU %.2f over %.1f px\n", level, k,
                  gpu[k].log_edges, gpu[k].edge_length, cpu.log_edges, cpu.length);
      ASSERT_GT(cpu.length, 100.0 / (1 << level));
      // The depth map's tolerance and the ray cast differ on a few samples at occluders' edges.
      EXPECT_NEAR(gpu[k].edge_length, cpu.length, 0.02 * cpu.length);
      EXPECT_NEAR(gpu[k].log_edges, cpu.log_edges, 0.03 * cpu.length);
    }
  }
}

TEST_F(EdgeTerm, ItAddsToTheTotalAndChangesNothingElse) {
  const test::SynthBoxScene& box = Box();
  SurfaceLikelihood with(device(), box.scene, Options(true)), without(device(), box.scene, Options(false));
  const std::vector<std::vector<double>> batch = {box.truth, test::With(box.scene, box.truth, "w", box.truth[3] + 0.05)};
  const std::vector<Evaluation> a = with.Evaluate(batch), b = without.Evaluate(batch);
  for (size_t k = 0; k < batch.size(); ++k) {
    EXPECT_EQ(a[k].log_likelihood, b[k].log_likelihood);
    EXPECT_EQ(a[k].log_occlusion_prior, b[k].log_occlusion_prior);
    EXPECT_EQ(b[k].log_edges, 0.0);
    EXPECT_EQ(b[k].edge_length, 0.0);
    EXPECT_DOUBLE_EQ(a[k].total(), b[k].total() + a[k].log_edges);
  }
}

TEST_F(EdgeTerm, ADumpKeepsEachEdgesShare) {
  // The sandwich's blocks of the edge term (NoiseCalibration.cpp): per camera and edge, the
  // sums whose total is the evaluation's.
  const test::SynthBoxScene& box = Box();
  SurfaceLikelihood likelihood(device(), box.scene, Options(true));
  Evaluation e;
  const SurfaceDump dump = likelihood.EvaluateAndDump(box.truth, &e);
  ASSERT_EQ(dump.edges.height, int(box.scene.cameras.size()));
  EXPECT_EQ(size_t(dump.edges.width), FindModelEdges(likelihood.geometry()).size());
  double sum = 0.0, length = 0.0;
  int scored = 0;
  for (int c = 0; c < dump.edges.height; ++c)
    for (int k = 0; k < dump.edges.width; ++k) {
      sum += dump.edges.At(k, c)[0];
      length += dump.edges.At(k, c)[1];
      scored += dump.edges.At(k, c)[1] > 0.0f;
    }
  EXPECT_NEAR(sum, e.log_edges, 1e-3 * std::abs(e.log_edges));
  EXPECT_NEAR(length, e.edge_length, 1e-3 * e.edge_length);
  // Each camera sees some of the box's twelve edges and the ground's border, never all.
  EXPECT_GT(scored, dump.edges.height * 4);
  EXPECT_LT(scored, dump.edges.height * dump.edges.width);
  // Without the term there is nothing to keep.
  SurfaceLikelihood without(device(), box.scene, Options(false));
  EXPECT_TRUE(without.EvaluateAndDump(box.truth).edges.Empty());
}

TEST_F(EdgeTerm, MaskedPixelsAreNoEvidence) {
  // A sample whose probes touch a masked pixel (the camera's mask, the lens border, clutter)
  // is dropped, never scored against the black of a masked photograph.
  const test::SynthBoxScene& box = Box();
  SurfaceLikelihood likelihood(device(), box.scene, Options(true));
  const Evaluation all = likelihood.Evaluate({box.truth})[0];
  std::vector<Image> none, left;
  for (const CameraModel& c : box.scene.cameras) {
    none.emplace_back(c.width, c.height, 0.0f);
    Image half(c.width, c.height, 1.0f);
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width / 2; ++x)
        for (int k = 0; k < 4; ++k) half.At(x, y)[k] = 0.0f;
    left.push_back(std::move(half));
  }
  likelihood.SetClutterMasks(none);
  const Evaluation masked = likelihood.Evaluate({box.truth})[0];
  EXPECT_EQ(masked.edge_length, 0.0);
  EXPECT_EQ(masked.log_edges, 0.0);
  likelihood.SetClutterMasks(left);
  const Evaluation half = likelihood.Evaluate({box.truth})[0];
  EXPECT_GT(half.edge_length, 0.2 * all.edge_length);
  EXPECT_LT(half.edge_length, 0.8 * all.edge_length);
  likelihood.ClearClutterMasks();
  EXPECT_EQ(likelihood.Evaluate({box.truth})[0].log_edges, all.log_edges);
}

TEST_F(EdgeTerm, TheTrueBoxEdgesBeatShiftedOnes) {
  // Noise-free photographs of a textured box on textured ground: the box's outline and creases
  // lie on the photographs' edges at the truth and not a few pixels off it (at 150 px focal
  // length and 1.9 m, 4 cm is about 3 pixels).
  const test::SynthBoxScene& box = Box();
  SurfaceLikelihood likelihood(device(), box.scene, Options(true));
  std::vector<std::vector<double>> batch = {box.truth};
  for (const auto& [name, step] : {std::pair<const char*, double>{"x", 0.04}, {"y", 0.04}, {"w", 0.08}, {"h", 0.06}})
    for (const double sign : {-1.0, 1.0}) {
      const size_t p = size_t(std::find_if(box.scene.parameters.begin(), box.scene.parameters.end(),
                                           [&](const auto& q) { return q.name == name; }) -
                              box.scene.parameters.begin());
      batch.push_back(test::With(box.scene, box.truth, name, box.truth[p] + sign * step));
    }
  for (size_t first = 0; first < batch.size(); first += 4) {
    const std::vector<std::vector<double>> part(batch.begin() + long(first),
                                                batch.begin() + long(std::min(first + 4, batch.size())));
    const std::vector<Evaluation> e = likelihood.Evaluate(part);
    static double truth = 0.0;
    if (first == 0) truth = e[0].log_edges;
    for (size_t k = first == 0 ? 1 : 0; k < e.size(); ++k) {
      std::printf("  hypothesis %zu: edges %.1f (truth %.1f)\n", first + k, e[k].log_edges, truth);
      EXPECT_LT(e[k].log_edges, truth - 20.0) << "hypothesis " << first + k;
    }
  }
}

}  // namespace
}  // namespace vkr
