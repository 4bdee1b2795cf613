// A house photographed in front of a plain cloth (assets/house_cloth): where does today's
// likelihood put it, and what pays for the move? The study behind these tests is in
// docs/internals/DECISIONS.md, 2026-11-27 ("The evidence at the edges"), with the command that
// takes the bias apart (scripts/edge_study.py).
//
// The enabled tests guard the asset and document today's behaviour: the mode lies off the
// truth, with the roof's overhang shrunk, and the occlusion prior's charge for texels one view
// sees — not photo-consistency — pays for it; a CPU edge score prefers the truth, and with the
// likelihood's edge term (likelihood.edges) the ridge stays where it is. The
// DISABLED_ tests state what a fixed likelihood must do (the truth is the best point along
// each line through it) and fail today, with the edge term too; run them with
//   build/tests/pipelines_tests --gtest_also_run_disabled_tests --gtest_filter='EdgeBias*'

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <tuple>

#include "engine/image/Image.h"
#include "pipelines/likelihood/LikelihoodTool.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"
#include "pipelines/rendering/ViewRendering.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"
#include "tests/pipelines/SynthesisedAsset.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;

const fs::path kAsset = fs::path(VKRECON_SOURCE_DIR) / "assets" / "house_cloth";

// The asset's parameters in scene order, at the truth (truth.json) and at the mode
// `vkrecon fit` finds from the truth on these photographs (the study's "all" row).
const char* const kNames[] = {"x", "y", "yaw", "w", "d", "h", "rh", "e", "wl", "wh"};
constexpr double kTruth[] = {0.0, -0.25, 8.0, 1.0, 0.8, 0.5, 0.35, 0.04, 0.45, 0.32};
constexpr double kTodaysMode[] = {0.00214, -0.25225, 8.0111, 0.99854, 0.81184,
                                  0.50153, 0.35695,  0.01868, 0.45714, 0.32853};

// The truth with its ridge slid back and up in the plane of the front slope: d/2 + e and rh
// grow by the factor 1 + s, the front wall and the roof's pitch stay.
std::vector<double> RidgeSlidBack(double s) {
  std::vector<double> psi(std::begin(kTruth), std::end(kTruth));
  psi[4] = 2 * ((kTruth[4] / 2 + kTruth[7]) * (1 + s) - kTruth[7]);
  psi[6] = kTruth[6] * (1 + s);
  return psi;
}

// A CPU edge score, a candidate for the evidence today's likelihood lacks: the colour
// contrast in photograph `photo` across the hypothesis's silhouette `silhouette` (alpha ≥ ½
// inside), averaged over the silhouette's pixels. The contour runs half a pixel outside each
// silhouette pixel that has a neighbour outside, along the normal (alpha's gradient); the
// photograph is compared `offset` pixels inside and outside it. Pixels on the image border
// are skipped (the frame cuts the silhouette there, no edge does).
double SilhouetteContrast(const Image& silhouette, const Image& photo, double offset = 1.0) {
  auto alpha = [&](int x, int y) { return silhouette.At(x, y)[3]; };
  double sum = 0.0;
  int pixels = 0;
  for (int y = 1; y + 1 < silhouette.height; ++y)
    for (int x = 1; x + 1 < silhouette.width; ++x) {
      if (alpha(x, y) < 0.5f) continue;
      if (alpha(x - 1, y) >= 0.5f && alpha(x + 1, y) >= 0.5f && alpha(x, y - 1) >= 0.5f && alpha(x, y + 1) >= 0.5f)
        continue;
      double gx = alpha(x + 1, y) - alpha(x - 1, y), gy = alpha(x, y + 1) - alpha(x, y - 1);
      const double norm = std::hypot(gx, gy);
      if (norm == 0.0) continue;
      gx /= norm, gy /= norm;  // towards the inside
      float in[4], out[4];
      const double cx = x + 0.5 - 0.5 * gx, cy = y + 0.5 - 0.5 * gy;  // on the contour
      SampleBilinear(photo, cx + offset * gx, cy + offset * gy, in);
      SampleBilinear(photo, cx - offset * gx, cy - offset * gy, out);
      sum += std::sqrt(double((in[0] - out[0]) * (in[0] - out[0]) + (in[1] - out[1]) * (in[1] - out[1]) +
                              (in[2] - out[2]) * (in[2] - out[2])));
      ++pixels;
    }
  return pixels ? sum / pixels : 0.0;
}

class EdgeBias : public test::GpuTest {
 protected:
  // The photographs of synth.json at the truth, quarter size (160 × 120), noise 8, seed 7:
  // the study's images.
  void SetUp() override {
    GpuTest::SetUp();
    test::SynthesiseAssetImages(device(), "house_cloth", 8.0, dir_, "synth.json");
  }

  LikelihoodToolOptions Options(const fs::path& at) const {
    LikelihoodToolOptions options;
    options.scene_file = kAsset / "scene.json";
    options.overrides = {{"cameras", (dir_ / "cameras.json").string()},
                         {"images", dir_.path().string()},
                         {"likelihood.sigma", edges_ ? "8" : "4"}};
    options.overrides.push_back({"likelihood.edges", edges_ ? "true" : "false"});
    options.at_file = at;
    return options;
  }

  // Hypothesis `psi` (kNames' order) written as an --at file.
  fs::path WriteAt(const std::vector<double>& psi) const {
    std::ostringstream text;
    text << std::setprecision(17) << "{";
    for (size_t i = 0; i < std::size(kNames); ++i) text << (i ? ", " : "") << '"' << kNames[i] << "\": " << psi[i];
    text << "}";
    const fs::path file = dir_ / ("at_" + std::to_string(written_++) + ".json");
    test::WriteText(file, text.str());
    return file;
  }
  // truth + t (today's mode − truth).
  fs::path OnTheWayToTodaysMode(double t) const {
    std::vector<double> psi(std::size(kNames));
    for (size_t i = 0; i < psi.size(); ++i) psi[i] = kTruth[i] + t * (kTodaysMode[i] - kTruth[i]);
    return WriteAt(psi);
  }
  // The truth with parameter `name` at `value`.
  fs::path AtTheTruthWith(const std::string& name, double value) const {
    std::vector<double> psi(std::begin(kTruth), std::end(kTruth));
    for (size_t i = 0; i < psi.size(); ++i)
      if (kNames[i] == name) psi[i] = value;
    return WriteAt(psi);
  }

  Evaluation At(const fs::path& at) const { return EvaluateAt(Options(at), device()).evaluation; }

  // The swept value with the highest log-likelihood (printing the profile).
  double BestOfSweep(const std::string& sweep) const {
    const SweepResult result = Sweep(Options(kAsset / "truth.json"), ParseSweep(sweep), device());
    const SweepRow* best = &result.rows.front();
    for (const SweepRow& row : result.rows) {
      std::printf("  %s %.4f: total %.1f (photo-consistency %.1f, occlusion prior %.1f, edges %.1f over %.0f px)\n",
                  result.spec.parameter.c_str(), row.value, row.evaluation.total(), row.evaluation.log_likelihood,
                  row.evaluation.log_occlusion_prior, row.evaluation.log_edges, row.evaluation.edge_length);
      if (row.evaluation.total() > best->evaluation.total()) best = &row;
    }
    return best->value;
  }

  // The edge score of a hypothesis: SilhouetteContrast of the house alone (the model without
  // its ground) over the six photographs, summed.
  double EdgeScore(const fs::path& at) const {
    const fs::path house = dir_ / "house_only.json";
    if (!fs::exists(house)) {
      nlohmann::json scene = nlohmann::json::parse(std::ifstream(kAsset / "scene.json"));
      nlohmann::json nodes = nlohmann::json::array();
      for (nlohmann::json& node : scene["nodes"]) {
        if (node["name"] == "ground") continue;
        if (node.contains("albedo")) node["albedo"] = (kAsset / node["albedo"].get<std::string>()).string();
        nodes.push_back(node);
      }
      scene["nodes"] = nodes;
      test::WriteText(house, scene.dump(2));
    }
    RenderOptions render;
    render.scene_file = house;
    render.overrides = {{"cameras", (dir_ / "cameras.json").string()}};
    render.at_file = at;
    render.atlas = 256;
    render.output = dir_ / "silhouette";
    double score = 0.0;
    for (const fs::path& view : RenderViews(render, device()))
      score += SilhouetteContrast(LoadImage(view), LoadImage(dir_ / (view.stem().string() + ".png")));
    return score;
  }

  test::TempDir dir_;
  mutable int written_ = 0;  // --at files written
  // Score with the edge term, at σ 8: the photographs' noise, which a run estimates. (The
  // study's σ 4 passes half the noise-only pixel pairs for contrasts, and the edge term then
  // weighs a third as much.)
  bool edges_ = false;
};

TEST_F(EdgeBias, TodaysModeShrinksTheOverhangAndTheOcclusionPriorPaysForIt) {
  for (int i = 0; i < 6; ++i) {
    const fs::path image = dir_ / ("cam" + std::to_string(i) + ".png");
    ASSERT_TRUE(fs::exists(image)) << image;
    EXPECT_GT(fs::file_size(image), 1000u) << image;
  }
  const Evaluation truth = At(kAsset / "truth.json"), mode = At(OnTheWayToTodaysMode(1.0));
  std::printf("  truth: total %.1f = %.1f %+.1f, one view %u; today's mode: total %.1f = %.1f %+.1f, one view %u\n",
              truth.total(), truth.log_likelihood, truth.log_occlusion_prior, truth.scalars.seen_once, mode.total(),
              mode.log_likelihood, mode.log_occlusion_prior, mode.scalars.seen_once);
  // Today the mode beats the truth by far more than noise could (measured: 743 nats) ...
  EXPECT_GT(mode.total(), truth.total() + 200.0);
  // ... though the photographs agree better at the truth: the occlusion prior pays for the move,
  // by charging the true overhang for the texels fewer than two views see.
  EXPECT_LT(mode.log_likelihood, truth.log_likelihood);
  EXPECT_GT(mode.log_occlusion_prior, truth.log_occlusion_prior + 400.0);
  EXPECT_LT(mode.scalars.seen_once, truth.scalars.seen_once);
  // Along the depth and the roof's height alone, the likelihood peaks at the truth (0.8, 0.35):
  // the bias is not in a single one of them.
  EXPECT_NEAR(BestOfSweep("d=0.72:0.88:9"), 0.8, 1e-9);
  EXPECT_NEAR(BestOfSweep("rh=0.31:0.39:9"), 0.35, 1e-9);
}

// Fails today: the best overhang is 0.02 without the edge term, 0.03 with it (the edge term is
// flat within half a pixel, 1,922 nats at both 0.03 and 0.04, while the occlusion prior pays
// 380 for the smaller overhang; photo-consistency alone peaks at 0.03–0.04).
TEST_F(EdgeBias, DISABLED_TheTrueOverhangIsTheBestAlongTheOverhang) {
  edges_ = true;
  EXPECT_NEAR(BestOfSweep("e=0:0.08:9"), 0.04, 1e-9);
}

// Fails today: without the edge term the likelihood climbs from the truth all the way to
// today's mode; with it, halfway (t = 0.5: the edge term loses 100 nats there and 860 at the
// mode, the occlusion prior gains 400 and 850).
TEST_F(EdgeBias, DISABLED_TheTruthIsTheBestOnTheLineToTodaysMode) {
  edges_ = true;
  double best_t = 0.0, best = -1e300;
  for (const double t : {-0.5, -0.25, 0.0, 0.25, 0.5, 0.75, 1.0, 1.25}) {
    const Evaluation e = At(OnTheWayToTodaysMode(t));
    std::printf("  t %.2f: total %.1f (photo-consistency %.1f, occlusion prior %.1f, edges %.1f over %.0f px)\n", t,
                e.total(), e.log_likelihood, e.log_occlusion_prior, e.log_edges, e.edge_length);
    if (e.total() > best) best = e.total(), best_t = t;
  }
  EXPECT_EQ(best_t, 0.0);
}

// With the ridge slid back (the house deeper, its ridge higher, the pitch kept) the likelihood
// without the edge term peaks at s = +0.075 (d +8 %), and at +0.175 where the chimneys are left
// out of the photographs too. The edge term brings the peak back to the truth: the slid ridge
// and eaves leave the photographs' edges (1,922 nats at the truth, 1,073 at s = +0.05).
TEST_F(EdgeBias, WithEdgesTheTruthIsTheBestWithTheRidgeSlidBack) {
  edges_ = true;
  double best_s = 0.0, best = -1e300;
  for (int k = -4; k <= 8; ++k) {
    const double s = 0.025 * k;
    const Evaluation e = At(WriteAt(RidgeSlidBack(s)));
    std::printf("  s %+.3f: total %.1f (photo-consistency %.1f, occlusion prior %.1f, edges %.1f over %.0f px)\n", s,
                e.total(), e.log_likelihood, e.log_occlusion_prior, e.log_edges, e.edge_length);
    if (e.total() > best) best = e.total(), best_s = s;
  }
  EXPECT_EQ(best_s, 0.0);
}

// What pays for today's mode is the occlusion prior's charge for texels one view sees: without
// it (unverified_penalty 0, the colour correction fitted at the truth for both) the truth
// beats the ridge slid 7.5 % back and the overhang halved, and today's mode keeps under a
// tenth of its gain (measured: 756 nats with the charge, 32 without).
TEST_F(EdgeBias, WithoutTheChargeForOneViewTexelsTheTruthBeatsTodaysMode) {
  const Scene scene = LoadScene(kAsset / "scene.json", Options(kAsset / "truth.json").overrides);
  const std::vector<double> truth(std::begin(kTruth), std::end(kTruth)), mode(std::begin(kTodaysMode),
                                                                             std::end(kTodaysMode));
  const std::vector<double> ridge = RidgeSlidBack(0.075);
  std::vector<double> halved = truth;
  halved[7] = kTruth[7] / 2;
  const std::vector<std::vector<double>> batch = {truth, mode, ridge, halved};
  auto evaluate = [&](double penalty) {
    SurfaceLikelihoodOptions options = SurfaceLikelihoodOptions::FromScene(scene);
    options.model.unverified_penalty = penalty;
    SurfaceLikelihood likelihood(device(), scene, options);
    likelihood.SetPhotometric(
        FitPhotometric(likelihood.EvaluateAndDump(truth).view_textures, likelihood.options().photometric));
    const std::vector<Evaluation> e = likelihood.Evaluate(batch);
    std::printf("  one-view charge %.0f: truth %.1f, today's mode %+.1f, ridge back %+.1f, overhang halved %+.1f\n",
                penalty, e[0].total(), e[1].total() - e[0].total(), e[2].total() - e[0].total(),
                e[3].total() - e[0].total());
    return e;
  };
  const std::vector<Evaluation> charged = evaluate(1.0), free = evaluate(0.0);
  for (size_t i = 1; i < batch.size(); ++i)
    EXPECT_GT(charged[i].total(), charged[0].total()) << "today, hypothesis " << i << " beats the truth";
  EXPECT_LT(free[1].total() - free[0].total(), 0.1 * (charged[1].total() - charged[0].total()));
  EXPECT_LT(free[2].total(), free[0].total()) << "without the charge the truth beats the ridge slid back";
  EXPECT_LT(free[3].total(), free[0].total()) << "without the charge the truth beats the halved overhang";
}

// The CPU edge score along the line from the truth to today's mode, with the ridge slid back,
// and along the depth, the roof's height and the overhang: unlike the likelihood, it prefers
// the truth to today's mode and to the ridge slid back, and its profiles peak within a step of
// the truth (steps of about half a pixel in the photographs' 160 × 120).
TEST_F(EdgeBias, TheEdgeScorePrefersTheTruthToTodaysMode) {
  auto best_of = [&](const std::vector<std::pair<double, fs::path>>& points, const char* what) {
    double best_value = 0.0, best = -1.0;
    for (const auto& [value, at] : points) {
      const double score = EdgeScore(at);
      std::printf("  %s %.3f: edge score %.4f\n", what, value, score);
      if (score > best) best = score, best_value = value;
    }
    return best_value;
  };
  std::vector<std::pair<double, fs::path>> line;
  for (const double t : {-0.5, -0.25, 0.0, 0.25, 0.5, 0.75, 1.0, 1.25}) line.emplace_back(t, OnTheWayToTodaysMode(t));
  EXPECT_EQ(best_of(line, "t"), 0.0);
  std::vector<std::pair<double, fs::path>> ridge;
  for (int k = -4; k <= 8; ++k) ridge.emplace_back(0.025 * k, WriteAt(RidgeSlidBack(0.025 * k)));
  EXPECT_EQ(best_of(ridge, "ridge s"), 0.0);
  // name, truth, step: sweeps of ± 4 steps.
  const std::tuple<const char*, double, double> sweeps[] = {{"d", 0.8, 0.01}, {"rh", 0.35, 0.005}, {"e", 0.04, 0.005}};
  for (const auto& [name, truth, step] : sweeps) {
    std::vector<std::pair<double, fs::path>> points;
    for (int k = -4; k <= 4; ++k) points.emplace_back(truth + k * step, AtTheTruthWith(name, truth + k * step));
    EXPECT_NEAR(best_of(points, name), truth, 1.01 * step) << name;
  }
}

}  // namespace
}  // namespace vkr
