// "atlas": "auto" (engine/geometry/AtlasFootprint.h): the bundled assets, whose 256² atlases
// docs/NOISE_STUDY.md validated at 640 × 480, get 256 by the rule; the atlas follows the
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
    Scene scene = LoadAsset(asset);
    ASSERT_EQ(scene.likelihood.atlas, 0);  // "auto" until resolved
    ResolveAutoLikelihood(scene);
    EXPECT_EQ(scene.likelihood.atlas, 256);
    EXPECT_EQ(scene.likelihood.levels, 3);
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

}  // namespace
}  // namespace vkr
