// assets/house_annex/scene_eaves.json is what a user writes who sees the roof overhang the
// walls (docs/guide/REAL_PHOTOS.md, "The synthetic clutter assets"): at the truth and the true
// overhang it must build the roof the photographs were rendered with (synth.json), which
// the plain scene cannot, or the variant would fix a model error by making another.

#include <gtest/gtest.h>

#include <string>

#include "engine/scene/Scene.h"

namespace vkr {
namespace {

const std::string kHouseAnnex = std::string(VKRECON_SOURCE_DIR) + "/assets/house_annex/";

Scene LoadWithoutImages(const std::string& file) {
  LoadOptions load;
  load.require_images = false;
  return LoadScene(kHouseAnnex + file, {}, load);
}

int NodeIndex(const Scene& scene, const std::string& name) {
  for (size_t i = 0; i < scene.nodes.size(); ++i)
    if (scene.nodes[i].name == name) return int(i);
  ADD_FAILURE() << "no node " << name;
  return 0;
}

// The truth of assets/house_annex/truth.json (and the overhang make_assets.py builds, 3 cm)
// in the order of the scene's parameters.
std::vector<double> AtTheTruth(const Scene& scene) {
  std::vector<double> psi(scene.parameters.size(), 0.0);
  const std::pair<const char*, double> truth[] = {{"x", 0.1}, {"y", 0.05}, {"yaw", -12.0}, {"w", 1.1},
                                                  {"d", 0.8}, {"h", 0.6},  {"rh", 0.35},   {"e", 0.03}};
  for (const auto& [name, value] : truth)
    if (const int i = scene.ParameterIndex(name); i >= 0) psi[size_t(i)] = value;
  return psi;
}

Eigen::Matrix4d RoofAtTheTruth(const Scene& scene) {
  return scene.WorldFromNode(AtTheTruth(scene))[size_t(NodeIndex(scene, "roof"))];
}

TEST(AssetVariants, TheEavesSceneBuildsTheRoofTheHouseAnnexPhotographsShow) {
  const Scene eaves = LoadWithoutImages("scene_eaves.json");
  const Scene plain = LoadWithoutImages("scene.json");
  const Scene photographed = LoadWithoutImages("synth.json");
  ASSERT_GE(eaves.ParameterIndex("e"), 0);
  const Eigen::Matrix4d truth = RoofAtTheTruth(photographed);
  EXPECT_LT((RoofAtTheTruth(eaves) - truth).norm(), 1e-9) << RoofAtTheTruth(eaves) << "\n" << truth;
  // The plain scene's roof is flush with the walls: 6 cm shorter and narrower.
  const Eigen::Matrix4d flush = RoofAtTheTruth(plain);
  EXPECT_NEAR(truth.col(0).head<3>().norm() - flush.col(0).head<3>().norm(), 0.06, 1e-9);
  EXPECT_NEAR(truth.col(1).head<3>().norm() - flush.col(1).head<3>().norm(), 0.06, 1e-9);
}

}  // namespace
}  // namespace vkr
