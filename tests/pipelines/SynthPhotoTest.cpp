// `synth` renders photograph-like references: a sun lights faces by their angle to it and
// the scene casts shadows (a depth map from the sun), an exposure differs per camera and is
// recorded, and the scene's `synth` block sets all of it.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "engine/image/Exposure.h"
#include "engine/image/Image.h"
#include "pipelines/rendering/ViewRendering.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

using test::GpuTest;

// A 0.4 m cube on grey ground (no albedo: 0.5 encoded), a camera straight above it, the
// sun in the +x direction 45° high: the cube's shadow lies on the ground towards −x, from
// its edge at x = −0.2 to x = −0.6.
constexpr const char* kScene = R"({
  "version": 1,
  "parameters": {"h": {"prior": {"uniform": [0.1, 1]}, "init": 0.4}},
  "nodes": [{"name": "ground", "primitive": "plane", "transforms": [{"scale": [4, 4, 1]}]},
            {"name": "cube", "primitive": "box", "transforms": [{"scale": [0.4, 0.4, "h"]}]}],
  "cameras": [{"name": "top", "image": "top.png", "width": 200, "height": 200,
               "K": [[100, 0, 100], [0, 100, 100], [0, 0, 1]],
               "R": [[1, 0, 0], [0, -1, 0], [0, 0, -1]], "t": [0, 0, 2.0]}],
  "synth": {"sun": [0, 45], "ambient": 0.3, "supersample": 2}
})";

// Encoded value a pixel of the camera above shows at world (x, y, z).
double Grey(const Image& image, double x, double y, double z) {
  // x_cam = (x, −y, 2 − z): u = 100 x / (2 − z) + 100, v = −100 y / (2 − z) + 100.
  const int u = int(std::floor(100.0 * x / (2.0 - z) + 100.0));
  const int v = int(std::floor(-100.0 * y / (2.0 - z) + 100.0));
  return image.At(u, v)[1];
}

double Encoded(double linear) { return LinearToSrgb(float(linear)); }

TEST_F(GpuTest, SynthLightsFacesByTheSunAndCastsShadows) {
  test::TempDir dir;
  test::WriteText(dir / "scene.json", kScene);
  test::WriteText(dir / "at.json", R"({"h": 0.4})");
  SynthOptions options;
  options.scene_file = dir / "scene.json";
  options.at_file = dir / "at.json";
  options.output_dir = dir / "out";
  options.atlas = 256;
  SynthesiseImages(options, device());
  const Image image = LoadImage(dir / "out" / "top.png");

  const double albedo = SrgbToLinear(0.5f);
  const double lit_ground = Encoded(albedo * (0.3 + 0.7 * std::sin(M_PI / 4)));
  const double shadowed = Encoded(albedo * 0.3);
  EXPECT_NEAR(Grey(image, 0.9, 0.0, 0.0), lit_ground, 3.0 / 255);   // open ground, lit
  EXPECT_NEAR(Grey(image, -0.4, 0.0, 0.0), shadowed, 3.0 / 255);    // in the cube's shadow
  EXPECT_NEAR(Grey(image, -0.4, 0.5, 0.0), lit_ground, 3.0 / 255);  // beside the shadow
  EXPECT_NEAR(Grey(image, 0.0, 0.0, 0.4), lit_ground, 3.0 / 255);   // the top, as lit as the ground
  EXPECT_NEAR(Grey(image, -0.8, 0.0, 0.0), lit_ground, 3.0 / 255);  // beyond the shadow's end

  // --unlit draws the albedo as it is.
  options.sun = false;
  options.output_dir = dir / "unlit";
  SynthesiseImages(options, device());
  const Image flat = LoadImage(dir / "unlit" / "top.png");
  EXPECT_NEAR(Grey(flat, -0.4, 0.0, 0.0), 0.5, 1.0 / 255);
  EXPECT_NEAR(Grey(flat, 0.9, 0.0, 0.0), 0.5, 1.0 / 255);
}

TEST_F(GpuTest, SynthGivesEachCameraItsOwnExposureAndRecordsIt) {
  test::TempDir dir;
  test::WriteText(dir / "scene.json", kScene);
  test::WriteText(dir / "at.json", R"({"h": 0.4})");
  SynthOptions options;
  options.scene_file = dir / "scene.json";
  options.at_file = dir / "at.json";
  options.atlas = 256;
  options.sun = false;
  options.output_dir = dir / "plain";
  SynthesiseImages(options, device());
  options.exposure = 0.35;
  options.output_dir = dir / "exposed";
  const SynthSummary summary = SynthesiseImages(options, device());
  ASSERT_FALSE(summary.exposure_file.empty());
  const nlohmann::json record = nlohmann::json::parse(test::ReadText(summary.exposure_file));
  const nlohmann::json& e = record.at("exposures").at(0);
  EXPECT_EQ(e.at("camera"), "top");
  Exposure exposure;
  for (int c = 0; c < 3; ++c) exposure.gain[c] = e.at("gain")[c].get<double>();
  exposure.offset = e.at("offset_255").get<double>() / 255.0;
  exposure.gamma = e.at("gamma").get<double>();
  // The recorded exposure turns the plain image into the exposed one (up to 8-bit rounding).
  const Image plain = LoadImage(dir / "plain" / "top.png");
  const Image exposed = LoadImage(dir / "exposed" / "top.png");
  double worst = 0.0;
  for (size_t i = 0; i < plain.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(exposure.Apply(plain.rgba[i + c], c) - exposed.rgba[i + c]));
  EXPECT_LT(worst, 2.5 / 255);
  EXPECT_GT(std::abs(exposure.gain[0] - 1.0) + std::abs(exposure.offset) + std::abs(exposure.gamma - 1.0), 0.01);
}

}  // namespace
}  // namespace vkr
