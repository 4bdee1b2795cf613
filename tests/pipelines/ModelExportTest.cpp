// Reconstruction outputs: the glTF model reads back (through the project's own importer and
// tinygltf) with the right geometry and texture, and reprojections at the truth agree with
// the photographs.

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include "engine/geometry/Mesh.h"
#include "pipelines/rendering/ModelExport.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"
#include "pipelines/rendering/ViewRendering.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;
using test::GpuTest;

TEST_F(GpuTest, TexturedModelAndReprojectionsOfTheTruth) {
  test::TempDir dir;
  const fs::path root = fs::path(VKRECON_SOURCE_DIR) / "assets/box";
  SynthOptions synth;
  synth.scene_file = root / "scene.json";
  synth.at_file = root / "truth.json";
  synth.output_dir = dir / "images";
  synth.scale = 0.25;
  SynthesiseImages(synth, device());
  const Scene scene = LoadScene(root / "scene.json", {{"cameras", (dir / "images/cameras.json").string()},
                                                      {"images", (dir / "images").string()}});
  const std::vector<double> truth = scene.ValuesFromFile(root / "truth.json");
  SurfaceLikelihoodOptions options = SurfaceLikelihoodOptions::FromScene(scene);
  options.atlas = 128;
  options.levels = 1;
  SurfaceLikelihood likelihood(device(), scene, options);
  const Image raw = likelihood.EvaluateAndDump(truth).composite;
  const Image composite = DilateAtlas(raw);
  const SceneGeometry geometry = BuildSceneGeometry(scene, scene.InitialValues(), options.atlas, options.charts);

  // Dilation keeps every seen texel's colour and fills the texels beside the charts, so
  // bilinear filtering at a chart's border never reads black.
  int filled = 0;
  for (int y = 1; y + 1 < raw.height; ++y)
    for (int x = 1; x + 1 < raw.width; ++x) {
      if (raw.At(x, y)[3] > 0.0f) {
        for (int c = 0; c < 3; ++c) ASSERT_EQ(composite.At(x, y)[c], raw.At(x, y)[c]);
        continue;
      }
      const bool beside_chart = raw.At(x - 1, y)[3] > 0.0f || raw.At(x + 1, y)[3] > 0.0f ||
                                raw.At(x, y - 1)[3] > 0.0f || raw.At(x, y + 1)[3] > 0.0f;
      if (!beside_chart) continue;
      EXPECT_EQ(composite.At(x, y)[3], 1.0f) << x << "," << y;
      ++filled;
    }
  EXPECT_GT(filled, 0);

  const fs::path glb = dir / "model.glb";
  WriteTexturedGlb(glb, scene, geometry, truth, composite);
  const Mesh back = LoadGltfMesh(glb);
  EXPECT_EQ(back.TriangleCount(), int(geometry.indices.size() / 3));
  // Every vertex read back is a vertex of the scene at the truth, in world space.
  const std::vector<Eigen::Matrix4d> world = scene.WorldFromNode(truth);
  for (const Eigen::Vector3f& p : back.positions) {
    double best = 1e9;
    for (const GpuVertex& v : geometry.vertices) {
      const Eigen::Vector3d w = (world[v.node] * Eigen::Vector4d(v.position[0], v.position[1], v.position[2], 1)).head<3>();
      best = std::min(best, (w - p.cast<double>()).norm());
    }
    ASSERT_LT(best, 1e-5) << p.transpose();
  }
  tinygltf::Model model;
  std::string err, warn;
  tinygltf::TinyGLTF loader;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, glb.string())) << err;
  ASSERT_EQ(model.images.size(), 1u);
  EXPECT_EQ(model.images[0].width, composite.width);
  EXPECT_EQ(model.meshes.size(), 2u);  // ground and box
  EXPECT_EQ(model.materials[0].pbrMetallicRoughness.baseColorTexture.index, 0);

  const auto strips = WriteReprojections(dir / "reprojections", device(), scene, geometry, truth, composite, {});
  ASSERT_EQ(strips.size(), scene.cameras.size());
  for (const Reprojection& r : strips) {
    const fs::path& file = r.file;
    EXPECT_GT(r.pixels, 0);
    EXPECT_LT(r.rms_255, 16.0) << file;  // noise-free images of the truth: edges and resampling
    const Image strip = LoadImage(file);
    ASSERT_EQ(strip.width, 3 * 160);
    double diff = 0.0;
    for (int y = 0; y < strip.height; ++y)
      for (int x = 2 * 160; x < 3 * 160; ++x) diff += strip.At(x, y)[0] + strip.At(x, y)[1] + strip.At(x, y)[2];
    // |difference| ×4 at the truth: dark on average (edges and resampling only).
    EXPECT_LT(diff / (3.0 * 160 * strip.height), 0.12) << file;
    // The residual image: at the truth few pixels stand out.
    EXPECT_EQ(LoadImage(r.residual_file).width, 160);
    EXPECT_LT(r.outlier_share, 0.05) << r.residual_file;
  }
  // A box 15 cm off, textured with the truth's composite: its photographs' residuals show it.
  std::vector<double> wrong = truth;
  wrong[size_t(scene.ParameterIndex("x"))] += 0.15;
  const auto off = WriteReprojections(dir / "wrong", device(), scene, geometry, wrong, composite, {});
  double truth_share = 0.0, wrong_share = 0.0;
  for (size_t i = 0; i < off.size(); ++i) truth_share += strips[i].outlier_share, wrong_share += off[i].outlier_share;
  EXPECT_GT(wrong_share, 3.0 * truth_share);
}

}  // namespace
}  // namespace vkr
