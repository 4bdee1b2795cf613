// "No free surface" (docs/internals/LIKELIHOOD.md): surface whose photographs disagree — here a
// sign that shows each camera another picture, as a screen or a glossy sign would — must not gain
// by moving where only one camera sees it, which takes it out of the comparison. Without the
// occlusion prior's charge for surface one view alone sees, the sign slid out of two of the three
// cameras' frames beats the truth; with it, the truth wins.

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "pipelines/likelihood/SurfaceLikelihood.h"
#include "pipelines/rendering/ViewRendering.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;
using test::GpuTest;

// Three cameras side by side at x = −1, 0, 1, 3 m in front of the sign, looking along +y.
std::string Cameras() {
  std::ostringstream s;
  s.precision(17);
  for (int i = 0; i < 3; ++i) {
    const double x = i - 1.0;
    // R maps world (x, y, z) to camera (x, −z, y): looking along +y, image y down.
    s << (i ? ",\n" : "") << R"({"name": "cam)" << i << R"(", "image": "cam)" << i
      << R"(.png", "width": 160, "height": 120, "K": [[150, 0, 80], [0, 150, 60], [0, 0, 1]],
         "R": [[1, 0, 0], [0, 0, -1], [0, 1, 0]], "t": [)" << -x << ", 0.5, 3.0]}";
  }
  return s.str();
}

// The sign alone (the environment shows behind it), painted with `sign_albedo`.
std::string SceneJson(const std::string& sign_albedo) {
  return R"({
    "version": 1,
    "parameters": {"slide": {"prior": {"uniform": [-3, 3]}, "init": 0}},
    "nodes": [
      {"name": "sign", "primitive": "plane", "albedo": ")" + sign_albedo + R"(",
       "transforms": [{"translate": ["slide", 0, 0.5]}, {"rotate": [90, 0, 0]}, {"scale": [0.8, 0.6, 1]}]}],
    "cameras": [)" + Cameras() + R"(]
  })";
}

TEST_F(GpuTest, SurfaceGainsNothingByMovingWhereOnlyOneCameraSeesIt) {
  test::TempDir dir;
  const fs::path assets = fs::path(VKRECON_SOURCE_DIR) / "assets";
  const std::string pictures[3] = {(assets / "box/textures/box.png").string(),
                                   (assets / "house/textures/walls.png").string(),
                                   (assets / "poster/textures/poster.png").string()};
  test::WriteText(dir / "truth.json", R"({"slide": 0})");
  // Camera i photographs the sign showing picture i.
  for (int i = 0; i < 3; ++i) {
    const fs::path shot = dir / ("shot" + std::to_string(i));
    test::WriteText(shot / "scene.json", SceneJson(pictures[i]));
    SynthOptions synth;
    synth.scene_file = shot / "scene.json";
    synth.at_file = dir / "truth.json";
    synth.output_dir = shot;
    synth.noise_sigma = 4.0;
    synth.seed = uint64_t(i + 1);
    synth.atlas = 512;
    SynthesiseImages(synth, device());
    fs::copy_file(shot / ("cam" + std::to_string(i) + ".png"), dir / ("cam" + std::to_string(i) + ".png"));
  }
  test::WriteText(dir / "scene.json", SceneJson(pictures[0]));
  const Scene scene = LoadScene(dir / "scene.json");

  SurfaceLikelihoodOptions options = SurfaceLikelihoodOptions::FromScene(scene);
  options.atlas = 256;
  options.levels = 1;
  options.weights = ViewWeights::Uniform;
  options.model.sigma = 4.0;
  // Slid 2.1 m left, the sign is inside camera 0's frame only.
  const std::vector<std::vector<double>> batch = {{0.0}, {-2.1}};
  auto evaluate = [&](double unverified_penalty) {
    options.model.unverified_penalty = unverified_penalty;
    SurfaceLikelihood likelihood(device(), scene, options);
    return likelihood.Evaluate(batch);
  };
  const std::vector<Evaluation> free = evaluate(0.0), charged = evaluate(1.0);
  const ReducedScalars &truth = free[0].scalars, &escaped = free[1].scalars;
  std::printf("  truth: multi %u once %u none %u outliers %u/%u; escaped: multi %u once %u none %u\n",
              truth.seen_multi, truth.seen_once, truth.seen_none, truth.outlier_views, truth.views,
              escaped.seen_multi, escaped.seen_once, escaped.seen_none);
  std::printf("  without the charge truth %.0f escaped %.0f; with it truth %.0f escaped %.0f\n", free[0].total(),
              free[1].total(), charged[0].total(), charged[1].total());
  // The sign's views disagree at the truth, and the escape really leaves one view on it.
  EXPECT_GT(truth.outlier_views, truth.views / 4);
  EXPECT_GT(escaped.seen_once, truth.seen_once + truth.seen_multi / 4);
  EXPECT_GT(free[1].total(), free[0].total()) << "without the charge, escaping the comparison should pay";
  EXPECT_GT(charged[0].total(), charged[1].total()) << "with it the truth should win";
}

}  // namespace
}  // namespace vkr
