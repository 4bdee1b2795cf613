// The interior mask of a crowded scene against the CPU reference's, texel by texel. The
// interior pass carries, per vertex, the position in the frame of each primitive whose volume
// may hold the node's surface (at most four, chosen per hypothesis by bounding boxes) and
// tests every node per texel when there are more: this scene has both. The box scene of
// SurfaceLikelihoodTest has two nodes and never reaches the second path.

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "pipelines/rendering/ViewRendering.h"
#include "tests/common/GpuTest.h"
#include "tests/pipelines/SurfaceReference.h"

namespace vkr::test {
namespace {

// A ground, a cluster of five interpenetrating boxes (each holds parts of the other four and
// stands on the ground: five candidates, so every node per texel), and a lone box with a
// roof prism on top, far from the cluster (ground and roof only: the per-vertex path). The
// roof's base lies on the lone box's top; `x` moves the lone box and its roof along the
// diagonal, at 0 into the cluster (then they too test every node per texel).
struct CrowdedScene {
  std::unique_ptr<TempDir> dir = std::make_unique<TempDir>();
  Scene scene;
  std::vector<double> truth;
};

CrowdedScene MakeCrowdedScene(vk::Device& device) {
  CrowdedScene s;
  const std::string textures = VKRECON_SOURCE_DIR "/assets/box/textures/";
  auto box = [&](const std::string& name, double x, double y, double yaw, double w, double d, double h) {
    char text[512];
    std::snprintf(text, sizeof text,
                  R"({"name": "%s", "primitive": "box", "albedo": "%sbox.png", "transforms": )"
                  R"([{"translate": [%g, %g, 0]}, {"rotate": [0, 0, %g]}, {"scale": [%g, %g, %g]}]})",
                  name.c_str(), textures.c_str(), x, y, yaw, w, d, h);
    return std::string(text);
  };
  std::string cameras;
  for (int k = 0; k < 4; ++k) {
    const double a = (30.0 + 90.0 * k) * M_PI / 180.0;
    const Eigen::Vector3d eye(2.6 * std::cos(a), 2.6 * std::sin(a), 1.8);
    cameras += (k ? ",\n    " : "") +
               LookAtCameraJson("cam" + std::to_string(k), eye, {0.2, 0.1, 0.3}, 160, 120, 130.0, 80.0, 60.0);
  }
  const std::string scene = R"({
  "version": 1,
  "images": "images/",
  "parameters": {"x": {"prior": {"uniform": [-0.5, 1.5]}, "init": 1.0}},
  "nodes": [
    {"name": "ground", "primitive": "plane", "transforms": [{"scale": [4, 4, 1]}],
     "albedo": ")" + textures + R"(ground.png"},
    )" + box("a", -0.3, -0.3, 0, 0.5, 0.5, 0.5) + ",\n    " + box("b", -0.1, -0.3, 20, 0.5, 0.4, 0.6) + ",\n    " +
                            box("c", -0.3, -0.1, -15, 0.4, 0.5, 0.4) + ",\n    " +
                            box("d", -0.15, -0.15, 40, 0.45, 0.45, 0.7) + ",\n    " +
                            box("e", -0.25, -0.2, 5, 0.6, 0.3, 0.3) + R"(,
    {"name": "lone", "primitive": "box", "albedo": ")" + textures + R"(box.png",
     "transforms": [{"translate": ["x", "x", 0]}, {"scale": [0.5, 0.4, 0.4]}]},
    {"name": "roof", "primitive": "prism", "albedo": ")" + textures + R"(box.png",
     "transforms": [{"translate": ["x", "x", 0.4]}, {"scale": [0.5, 0.4, 0.25]}]}
  ],
  "cameras": [
    )" + cameras + R"(
  ]
})";
  const std::filesystem::path scene_file = *s.dir / "scene.json";
  WriteText(scene_file, scene);
  WriteText(*s.dir / "at.json", R"({"x": 1.0})");
  SynthOptions synth;
  synth.scene_file = scene_file;
  synth.at_file = *s.dir / "at.json";
  synth.output_dir = *s.dir / "images";
  synth.atlas = 256;
  SynthesiseImages(synth, device);
  s.scene = LoadScene(scene_file);
  s.truth = s.scene.ValuesFromFile(synth.at_file);
  return s;
}

class InteriorMask : public GpuTest {};

TEST_F(InteriorMask, AgreesWithTheReferenceWhereManyPrimitivesTouch) {
  const CrowdedScene crowded = MakeCrowdedScene(device());
  SurfaceLikelihoodOptions options;
  options.atlas = 256;
  options.levels = 1;
  options.max_batch = 1;
  const SceneGeometry geometry = BuildSceneGeometry(crowded.scene, crowded.scene.InitialValues(), options.atlas, options.charts);
  const auto pyramids = LoadReferencePyramids(crowded.scene, 1);
  SurfaceLikelihood likelihood(device(), crowded.scene, options);
  // At the truth, and with the lone box pushed into the cluster.
  for (double x : {1.0, 0.0}) {
    SCOPED_TRACE("x = " + std::to_string(x));
    const std::vector<double> psi = With(crowded.scene, crowded.truth, "x", x);
    const SurfaceDump dump = likelihood.EvaluateAndDump(psi);
    ReferenceTexels ref;
    ReferenceSurfaceScalars(crowded.scene, geometry, pyramids, psi, 0, options, &ref);
    ASSERT_EQ(dump.deviation.width, ref.side);
    int surface = 0, interior = 0, differ = 0;
    for (int j = 0; j < ref.side; ++j)
      for (int i = 0; i < ref.side; ++i) {
        const size_t t = size_t(j) * ref.side + i;
        const float* dev = dump.deviation.At(i, j);
        if (ref.state[t] == TexelState::OffSurface || dev[3] < 0.5f) continue;
        ++surface;
        const bool ref_interior = ref.state[t] == TexelState::Interior;
        interior += ref_interior;
        if ((dev[2] > 0.5f) != ref_interior) ++differ;
      }
    std::printf("  x = %.2f: surface %d, interior %d, differ %d\n", x, surface, interior, differ);
    // Not vacuous: the cluster hides much of its boxes in each other.
    EXPECT_GT(interior, surface / 20);
    // Both test positions in the unit frame of the other primitive with the same tolerance;
    // only texels within float rounding of a boundary may differ.
    EXPECT_LE(differ, surface / 500);
  }
}

}  // namespace
}  // namespace vkr::test
