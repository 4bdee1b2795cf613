// "atlas": "auto" (engine/geometry/AtlasFootprint.h): the bundled assets, whose 256² atlases
// docs/internals/NOISE_STUDY.md validated at 640 × 480, get 256 by the rule; the atlas follows the
// photographs' resolution; surface no camera sees needs no texels.

#include <gtest/gtest.h>

#include <cmath>

#include "engine/geometry/AtlasFootprint.h"
#include "engine/geometry/SceneGeometry.h"

namespace vkr {
namespace {

Scene LoadAsset(const std::string& name, std::vector<SceneOverride> overrides = {}) {
  LoadOptions load;
  load.require_images = false;
  overrides.push_back({"likelihood.atlas", "auto"});
  overrides.push_back({"likelihood.levels", "auto"});
  return LoadScene(std::string(VKRECON_SOURCE_DIR) + "/assets/" + name + "/scene.json", overrides, load);
}

TEST(AtlasFootprint, TheBundledAssetsGetTheAtlasTheirStudyValidated) {
  for (const char* asset : {"box", "house", "stairs", "poster"}) {
    SCOPED_TRACE(asset);
    const Scene scene = LoadAsset(asset);
    const int atlas = AutoAtlasSide(SurfaceFootprintPixels(scene, BuildMeshes(scene)));
    EXPECT_EQ(atlas, 256);
    EXPECT_EQ(AutoLevels(atlas), 3);
  }
}

TEST(AtlasFootprint, TheRuleFollowsThePixels) {
  const double at256 = 256.0 * 256.0 * kPixelsPerTexel * kPackingShare;
  EXPECT_EQ(AutoAtlasSide(at256), 256);
  EXPECT_EQ(AutoAtlasSide(4 * at256), 512);      // twice the resolution in each direction
  EXPECT_EQ(AutoAtlasSide(at256 / 4), 128);
  EXPECT_EQ(AutoAtlasSide(1.9 * at256), 256);    // the nearest power of two
  EXPECT_EQ(AutoAtlasSide(2.1 * at256), 512);
  EXPECT_EQ(AutoAtlasSide(0.0), kMinAutoAtlas);
  EXPECT_EQ(AutoAtlasSide(1e12), kMaxAutoAtlas);
  EXPECT_EQ(AutoLevels(64), 1);
  EXPECT_EQ(AutoLevels(128), 2);
  EXPECT_EQ(AutoLevels(2048), 3);
}

TEST(AtlasFootprint, SurfaceBehindTheCamerasCountsNothing) {
  Scene scene = LoadAsset("poster");
  const double seen = SurfaceFootprintPixels(scene, BuildMeshes(scene));
  ASSERT_GT(seen, 0.0);
  // The same cameras turned around (180° about their own y axis) see none of it.
  std::vector<Mesh> meshes = BuildMeshes(scene);
  for (CameraModel& c : scene.cameras) {
    c.R = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix() * c.R;
    c.t = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix() * c.t;
  }
  EXPECT_EQ(SurfaceFootprintPixels(scene, meshes), 0.0);
}

// ChartSizing::Pixels, likelihood.charts "pixels" (AtlasFootprint.h): texels follow what the photographs show.
TEST(AtlasFootprint, ChartDensitiesFollowThePixelsPerSquareMetre) {
  const Scene scene = LoadAsset("box");
  const std::vector<Mesh> meshes = BuildMeshes(scene);
  const std::vector<double> psi = scene.InitialValues();
  const std::vector<double> pixels = FacePixels(scene, meshes, psi);
  const std::vector<double> density = ChartDensities(scene, meshes, psi);
  ASSERT_EQ(density.size(), pixels.size());
  // Seen faces get √(pixels / area) up to a common factor, so their texels are in proportion
  // to their pixels; the face the box stands on is seen by no camera.
  const std::vector<Eigen::Matrix4d> world = scene.WorldFromNode(psi);
  size_t face = 0, box_bottom = 0;
  double texels_per_pixel = 0.0;
  int seen = 0;
  for (size_t n = 0; n < meshes.size(); ++n) {
    const Mesh& mesh = meshes[n];
    for (size_t f = 0; f < mesh.faces.size(); ++f, ++face) {
      if (scene.nodes[n].name == "box" && f == 5) box_bottom = face;  // Primitives.cpp: bottom last
      if (density[face] <= 0.25) continue;
      double area = 0.0;
      for (int t = mesh.faces[f].first_triangle; t < mesh.faces[f].first_triangle + mesh.faces[f].triangle_count; ++t) {
        Eigen::Vector3d p[3];
        for (int k = 0; k < 3; ++k)
          p[k] = (world[n] * mesh.positions[mesh.indices[size_t(3 * t + k)]].cast<double>().homogeneous()).head<3>();
        area += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
      }
      const double ratio = density[face] * density[face] * area / pixels[face];
      if (seen++ == 0) texels_per_pixel = ratio;
      EXPECT_NEAR(ratio / texels_per_pixel, 1.0, 1e-9) << "face " << face;
    }
  }
  EXPECT_GE(seen, 4);  // the ground, the top and the sides the ring of cameras looks at
  EXPECT_EQ(pixels[box_bottom], 0.0);
  // The unseen face keeps the floor: a quarter of the density that spreads every pixel evenly.
  double total_pixels = 0.0, smallest = 1e30;
  for (size_t f = 0; f < density.size(); ++f) {
    total_pixels += pixels[f];
    smallest = std::min(smallest, density[f]);
  }
  EXPECT_GT(total_pixels, 0.0);
  EXPECT_DOUBLE_EQ(density[box_bottom], smallest);
  EXPECT_DOUBLE_EQ(density[box_bottom], 0.25);
}

// FacePixels clips what lies behind a camera instead of dropping the whole triangle, so a
// ground plane that runs on under the cameras counts the part they look at.
TEST(AtlasFootprint, FacePixelsCountTheGroundInFrontOfTheCameras) {
  const Scene scene = LoadAsset("box");
  const std::vector<Mesh> meshes = BuildMeshes(scene);
  const std::vector<double> pixels = FacePixels(scene, meshes, scene.InitialValues());
  size_t face = 0;
  for (size_t n = 0; n < meshes.size(); ++n)
    for (size_t f = 0; f < meshes[n].faces.size(); ++f, ++face)
      if (scene.nodes[n].name == "ground") {
        EXPECT_GT(pixels[face], 0.05 * scene.cameras[0].width * scene.cameras[0].height);
        EXPECT_LE(pixels[face], double(scene.cameras[0].width) * scene.cameras[0].height);
      }
}

}  // namespace
}  // namespace vkr
