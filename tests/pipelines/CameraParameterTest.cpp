// Camera parameters estimated with the scene (docs/guide/CAMERA_PARAMETERS.md, thesis §4.5.3), on
// the `focal` asset: the box, photographed with a focal length 4 % longer than the calibration says
// (f = 1.04), the principal point 6 px right of it (px = 6) and cam4 8 cm higher than its recorded
// pose (dz = 0.08). The asset's cameras.json holds the nominal calibration with f, px and dz
// written into K and pose. For each of them, with every other parameter at the truth, the surface
// likelihood's profile across the prior (41 steps) peaks within one step of the truth, and the
// recorded calibration (f = 1, px = 0, dz = 0) scores clearly worse.
//
// The likelihood must read the images through the nominal calibration, as `vkrecon run
// assets/focal/scene.json --set images=DIR` does. The cameras.json that synth writes next to
// the images has K and pose folded at the truth: loading it instead would hand the
// likelihood the answer (the loader refuses it, as the first test checks). Quarter-size
// images (160×120) and a 128² atlas keep it to seconds on lavapipe, so the test reads them
// through a quarter-size copy of the asset's camera file, its expressions kept.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "engine/common/InputError.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"
#include "pipelines/rendering/ViewRendering.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"
#include "tests/pipelines/SynthesisedAsset.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;

const fs::path kFocal = fs::path(VKRECON_SOURCE_DIR) / "assets" / "focal";
constexpr double kScale = 0.25;  // 640×480 → 160×120, as SynthesiseAssetImages renders

// The asset's camera file at quarter size: K' = diag(s, s, 1)·K as synth scales it, with
// expressions wrapped ("560*f" → "0.25*(560*f)") so f, px and dz stay free. Poses are
// in metres and do not scale.
fs::path WriteNominalCameras(const test::TempDir& dir) {
  nlohmann::json file = nlohmann::json::parse(std::ifstream(kFocal / "cameras.json"));
  for (nlohmann::json& camera : file["cameras"]) {
    camera["width"] = int(std::lround(camera["width"].get<int>() * kScale));
    camera["height"] = int(std::lround(camera["height"].get<int>() * kScale));
    for (int row = 0; row < 2; ++row)
      for (nlohmann::json& k : camera["K"][row]) {
        if (k.is_string()) k = std::to_string(kScale) + "*(" + k.get<std::string>() + ")";
        else k = kScale * k.get<double>();
      }
  }
  const fs::path out = dir / "nominal_cameras.json";
  test::WriteText(out, file.dump(2));
  return out;
}

// The focal scene reading the images in `dir` through the nominal calibration.
Scene NominalScene(const test::TempDir& dir) {
  return LoadScene(kFocal / "scene.json", {{"cameras", WriteNominalCameras(dir).string()},
                                           {"images", dir.path().string()}});
}

class CameraParameterTest : public test::GpuTest {};

TEST_F(CameraParameterTest, SynthesisedCameraFileCannotStandInForTheCalibration) {
  test::TempDir dir;
  SynthesiseAssetImages(device(), "focal", 0.0, dir);
  // synth folds K and pose at --at: f, px and dz are then used nowhere, which the loader
  // refuses rather than estimating them against the true calibration.
  try {
    LoadScene(kFocal / "scene.json",
              {{"cameras", (dir / "cameras.json").string()}, {"images", dir.path().string()}});
    ADD_FAILURE() << "loading the synthesised cameras.json should fail";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "parameters.f") << e.what();
  }

  // The nominal cameras at the truth are the ones synth rendered with.
  const Scene scene = NominalScene(dir);
  const std::vector<double> truth = scene.ValuesFromFile(kFocal / "truth.json");
  const std::vector<Camera> nominal = scene.Cameras(scene.InitialValues());
  const std::vector<Camera> actual = scene.Cameras(truth);
  ASSERT_EQ(actual.size(), 9u);
  EXPECT_NEAR(actual[0].K(0, 0), kScale * 1.04 * 560, 1e-9);
  EXPECT_NEAR(actual[0].K(1, 1), kScale * 1.04 * 560, 1e-9);
  EXPECT_NEAR(actual[0].K(0, 2), kScale * (320 + 6), 1e-9);
  EXPECT_NEAR(actual[0].K(1, 2), kScale * 240, 1e-9);
  EXPECT_NEAR(nominal[0].K(0, 0), kScale * 560, 1e-9);
  const Eigen::Vector3d moved = actual[4].Centre() - nominal[4].Centre();
  EXPECT_NEAR(moved.z(), 0.08, 1e-9);
  EXPECT_NEAR(moved.head<2>().norm(), 0.0, 1e-9);
  EXPECT_NEAR((actual[3].Centre() - nominal[3].Centre()).norm(), 0.0, 1e-12);
}

class CameraParameterProfile : public test::GpuTest, public ::testing::WithParamInterface<double> {};

TEST_P(CameraParameterProfile, PeaksAtTheTruthAndBeatsTheNominalCalibration) {
  const double noise = GetParam();
  test::TempDir dir;
  SynthesiseAssetImages(device(), "focal", noise, dir);
  const Scene scene = NominalScene(dir);
  const std::vector<double> truth = scene.ValuesFromFile(kFocal / "truth.json");

  constexpr int kSteps = 41;
  SurfaceLikelihoodOptions options = SurfaceLikelihoodOptions::FromScene(scene);
  options.atlas = 128;
  options.levels = 1;
  options.max_batch = kSteps + 2;
  // σ of the model matches the noise (a floor of 4 for noise-free images, as in
  // LikelihoodProfileTest).
  options.model.sigma = std::max(4.0, noise);
  SurfaceLikelihood likelihood(device(), scene, options);

  // The camera parameters and the values the calibration records for them.
  const std::pair<const char*, double> recorded[] = {{"f", 1.0}, {"px", 0.0}, {"dz", 0.0}};
  for (const auto& [name, value] : recorded) {
    const int p = scene.ParameterIndex(name);
    ASSERT_GE(p, 0) << name;
    const Prior& prior = scene.parameters[size_t(p)].prior;
    ASSERT_EQ(prior.kind, Prior::Kind::Uniform);
    const double lo = prior.a, hi = prior.b, step = (hi - lo) / (kSteps - 1);
    // The profile, then the recorded value, then the truth itself.
    std::vector<std::vector<double>> batch(kSteps + 2, truth);
    for (int k = 0; k < kSteps; ++k) batch[size_t(k)][size_t(p)] = lo + k * step;
    batch[kSteps][size_t(p)] = value;
    const std::vector<Evaluation> e = likelihood.Evaluate(batch);

    int best = 0;
    for (int k = 1; k < kSteps; ++k)
      if (e[size_t(k)].total() > e[size_t(best)].total()) best = k;
    const double peak = lo + best * step;
    EXPECT_LE(std::abs(peak - truth[size_t(p)]), step * 1.0001)
        << "σ=" << noise << ": " << name << " peaks at " << peak << ", truth " << truth[size_t(p)]
        << " (step " << step << ")";
    // "Clearly": a likelihood ratio beyond e^100 (measured: hundreds to thousands).
    const double gap = e[kSteps + 1].total() - e[kSteps].total();
    EXPECT_GT(gap, 100.0) << "σ=" << noise << ": the recorded " << name << " = " << value
                          << " scores only " << gap << " below the truth " << truth[size_t(p)];
    RecordProperty(std::string("gap_") + name, std::to_string(gap));
  }
}

// The suite's name starts with CameraParameter so that one filter runs the whole file.
INSTANTIATE_TEST_SUITE_P(CameraParameter, CameraParameterProfile, ::testing::Values(0.0, 16.0),
                         [](const auto& info) { return "noise" + std::to_string(int(info.param)); });

}  // namespace
}  // namespace vkr
