// §7.4: without the χ² sample-size correction the likelihood prefers a hypothesis that
// hides surface; with it, the truth. A textured sign stands in front of the cameras; the
// wrong hypothesis turns it to face away from all of them. It occludes the same ground, but
// its own texels become back-facing and drop out of the comparison, and with them their
// noise: −S/2σ² rewards that. With the correction, texels at the noise level are neutral
// and the occlusion prior (surface no view sees) decides for the truth.

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "pipelines/SurfaceLikelihood.h"
#include "pipelines/ViewRendering.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;

std::string LookAt(const std::string& name, const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R << x.transpose(), y.transpose(), z.transpose();
  const Eigen::Vector3d t = -R * eye;
  std::ostringstream s;
  s.precision(17);
  s << R"({"name": ")" << name << R"(", "image": ")" << name << R"(.png", "width": 160, "height": 120,
          "K": [[150, 0, 80], [0, 150, 60], [0, 0, 1]], "R": [)";
  for (int r = 0; r < 3; ++r) s << (r ? ", " : "") << "[" << R(r, 0) << ", " << R(r, 1) << ", " << R(r, 2) << "]";
  s << R"(], "t": [)" << t.x() << ", " << t.y() << ", " << t.z() << "]}";
  return s.str();
}

using test::GpuTest;

TEST_F(GpuTest, ChiSquareCorrectionStopsHiddenSurfaceFromWinning) {
  test::TempDir dir;
  const fs::path textures = fs::path(VKRECON_SOURCE_DIR) / "assets/box/textures";
  std::string cameras;
  for (int i = 0; i < 5; ++i) {
    const double a = (-50.0 + 25.0 * i) * M_PI / 180.0;
    cameras += (i ? ",\n" : "") + LookAt("cam" + std::to_string(i), {3.0 * std::sin(a), -3.0 * std::cos(a), 1.3},
                                          {0.0, 0.0, 0.5});
  }
  // tilt 90°: the sign's face (+z of the plane) turns to −y, towards the cameras; −90°: away.
  test::WriteText(dir / "scene.json", R"({
    "version": 1,
    "parameters": {"tilt": {"prior": {"uniform": [-100, 100]}}},
    "nodes": [
      {"name": "ground", "primitive": "plane", "albedo": ")" + (textures / "ground.png").string() + R"(",
       "transforms": [{"scale": [4, 4, 1]}]},
      {"name": "sign", "primitive": "plane", "albedo": ")" + (textures / "box.png").string() + R"(",
       "transforms": [{"translate": [0, 0, 0.6]}, {"rotate": ["tilt", 0, 0]}, {"scale": [1, 0.8, 1]}]}],
    "cameras": [)" + cameras + R"(]
  })");
  test::WriteText(dir / "truth.json", R"({"tilt": 90})");
  SynthOptions synth;
  synth.scene_file = dir / "scene.json";
  synth.at_file = dir / "truth.json";
  synth.output_dir = dir.path();
  synth.noise_sigma = 16.0;
  synth.seed = 3;
  SynthesiseImages(synth, device());
  const Scene scene = LoadScene(dir / "scene.json");

  SurfaceLikelihoodOptions options = SurfaceLikelihoodOptions::FromScene(scene);
  // Texels no larger than pixels (LOD 0): the sampled noise is then the images' σ. (Coarser
  // texels average pixels and their noise, and the statistic falls below its expectation —
  // a known limit of the current noise model, see docs/LIKELIHOOD.md.)
  options.atlas = 512;
  options.levels = 1;
  options.weights = ViewWeights::Uniform;
  options.model.sigma = 16.0;
  const std::vector<std::vector<double>> batch = {{90.0}, {-90.0}};
  auto evaluate = [&](bool correction) {
    options.model.chi2_correction = correction;
    SurfaceLikelihood likelihood(device(), scene, options);
    return likelihood.Evaluate(batch);
  };
  const std::vector<Evaluation> plain = evaluate(false), corrected = evaluate(true);
  const Evaluation &truth = plain[0], &hidden = plain[1];
  // The wrong hypothesis really hides surface: fewer texels compared, more seen by none.
  EXPECT_LT(hidden.scalars.dof, 0.95 * truth.scalars.dof);
  EXPECT_GT(hidden.scalars.seen_none, truth.scalars.seen_none + 500);
  EXPECT_GT(plain[1].total(), plain[0].total()) << "without the correction hiding the sign should look better";
  EXPECT_GT(corrected[0].total(), corrected[1].total()) << "with the correction the truth should win";
}

}  // namespace
}  // namespace vkr
