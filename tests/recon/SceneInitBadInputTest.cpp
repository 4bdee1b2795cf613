// `vkrecon init` on bad input (recon/SceneInit.h): each refused with one InputError line that
// names what is wrong, before anything is written.

#include <gtest/gtest.h>

#include "recon/SceneInit.h"
#include "tests/recon/SyntheticColmap.h"
#include "tests/scene/SceneTestUtil.h"

namespace vkr::test {
namespace {

using recon::InitOptions;
using recon::InitScene;

InitOptions Options(const SyntheticColmap& s, const TempDir& dir) {
  InitOptions o;
  o.sparse = s.sparse;
  o.output = dir / "scene";
  return o;
}

TEST(InitBadInput, NoPoints) {
  TempDir dir;
  const SyntheticColmap s = MakeSyntheticColmap("box", dir.path(), false, 1, 0);
  EXPECT_TRUE(FailsWith([&] { InitScene(Options(s, dir)); }, {"sparse", "points3D", "0 points"}));
  EXPECT_FALSE(std::filesystem::exists(dir / "scene"));
}

TEST(InitBadInput, OneCamera) {
  TempDir dir;
  const SyntheticColmap s = MakeSyntheticColmap("box", dir.path(), true, 1);
  RewriteColmap(s, [](ColmapReconstruction& m) { m.images.resize(1); });
  EXPECT_TRUE(FailsWith([&] { InitScene(Options(s, dir)); }, {"sparse", "1 registered image(s)", "at least two"}));
}

TEST(InitBadInput, NoGroundInPointsOnASphere) {
  TempDir dir;
  const SyntheticColmap s = MakeSyntheticColmap("box", dir.path(), false, 1);
  RewriteColmap(s, [&](ColmapReconstruction& m) {
    std::mt19937_64 rng(3);
    std::normal_distribution<double> normal(0.0, 1.0);
    for (ColmapPoint& p : m.points) {
      const Eigen::Vector3d on_sphere = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
      p.xyz = s.scale * (s.rotation * (on_sphere + Eigen::Vector3d(0, 0, 0.5))) + s.translation;
    }
  });
  EXPECT_TRUE(FailsWith([&] { InitScene(Options(s, dir)); }, {"sparse: points3D", "no ground found", "--up"}));
}

TEST(InitBadInput, TemplateDoesNotFitPointsOnTheGroundOnly) {
  TempDir dir;
  const SyntheticColmap s = MakeSyntheticColmap("house", dir.path(), false, 1);
  RewriteColmap(s, [&](ColmapReconstruction& m) {
    std::vector<ColmapPoint> kept;
    for (const ColmapPoint& p : m.points) {
      const Eigen::Vector3d truth = s.rotation.transpose() * (p.xyz - s.translation) / s.scale;
      if (truth.z() < 0.02 || kept.size() % 500 == 1) kept.push_back(p);
    }
    m.points = kept;
  });
  InitOptions o = Options(s, dir);
  o.template_kind = recon::InitTemplate::House;
  EXPECT_TRUE(FailsWith([&] { InitScene(o); }, {"sparse: points3D", "house template does not fit", "above the ground"}));
}

// A ring of cameras around a box: two of its faces meet in a corner, but the cameras that
// see the backs of those faces are no inside corner's.
TEST(InitBadInput, CornerTemplateDoesNotFitABoxSeenAllAround) {
  TempDir dir;
  const SyntheticColmap s = MakeSyntheticColmap("box", dir.path(), false, 1);
  InitOptions o = Options(s, dir);
  o.template_kind = recon::InitTemplate::Corner;
  EXPECT_TRUE(FailsWith([&] { InitScene(o); }, {"sparse: points3D", "corner template does not fit", "cameras stand between",
                                                 "box or house template"}));
  EXPECT_FALSE(std::filesystem::exists(dir / "scene/scene.json"));
}

TEST(InitBadInput, StairsTemplateDoesNotFitABox) {
  TempDir dir;
  const SyntheticColmap s = MakeSyntheticColmap("box", dir.path(), true, 2);
  InitOptions o = Options(s, dir);
  o.template_kind = recon::InitTemplate::Stairs;
  EXPECT_TRUE(FailsWith([&] { InitScene(o); }, {"sparse: points3D", "stairs template does not fit", "do not rise one way"}));
}

TEST(InitBadInput, MissingOrWrongPhotograph) {
  TempDir dir;
  const SyntheticColmap s = MakeSyntheticColmap("box", dir.path(), false, 1);
  std::filesystem::remove(s.images / "cam3.pgm");
  EXPECT_TRUE(FailsWith([&] { InitScene(Options(s, dir)); }, {"images/cam3.pgm", "photograph missing"}));
  WriteText(s.images / "cam3.pgm", "P5\n4 3\n255\n" + std::string(12, '\x80'));
  EXPECT_TRUE(FailsWith([&] { InitScene(Options(s, dir)); }, {"images/cam3.pgm", "is 4x3"}));
  InitOptions elsewhere = Options(s, dir);
  elsewhere.images = dir / "nowhere";
  EXPECT_TRUE(FailsWith([&] { InitScene(elsewhere); }, {"nowhere/cam0.pgm", "photograph missing"}));
}

TEST(InitBadInput, ExistingSceneAndBadOptions) {
  TempDir dir;
  const SyntheticColmap s = MakeSyntheticColmap("box", dir.path(), false, 1);
  InitScene(Options(s, dir));
  EXPECT_TRUE(FailsWith([&] { InitScene(Options(s, dir)); }, {"scene/scene.json", "does not overwrite"}));
  InitOptions o = Options(s, dir);
  o.output = dir / "other";
  o.scale = recon::ScalePoints{1, 2, 1.0};
  EXPECT_TRUE(FailsWith([&] { InitScene(o); }, {"--scale-points", "point 1 is not in"}));
  o.scale.reset();
  o.up = Eigen::Vector3d::Zero();
  EXPECT_TRUE(FailsWith([&] { InitScene(o); }, {"--up", "non-zero"}));
  EXPECT_TRUE(FailsWith([] { recon::ParseScalePoints("12,14"); }, {"--scale-points", "ID1,ID2=LENGTH"}));
  EXPECT_TRUE(FailsWith([] { recon::ParseScalePoints("12,14=-1"); }, {"--scale-points"}));
  const recon::ScalePoints ok = recon::ParseScalePoints("12,14=0.5");
  EXPECT_EQ(ok.a, 12u);
  EXPECT_EQ(ok.b, 14u);
  EXPECT_EQ(ok.length, 0.5);
}

// --up replaces the cameras' mean up: the same ground when it is right, none when it is a wall's.
TEST(InitUp, UserUpOverridesTheCameras) {
  TempDir dir;
  const SyntheticColmap s = MakeSyntheticColmap("house", dir.path(), false, 1);
  InitOptions o = Options(s, dir);
  o.up = s.rotation.col(2) + 0.2 * s.rotation.col(0);  // 11° off: the ground still lies within 45°
  const recon::InitResult r = InitScene(o);
  EXPECT_LT(std::acos(std::min(1.0, r.up.dot(s.rotation.col(2)))) * 180.0 / M_PI, 1.0);
  o.output = dir / "sideways";
  o.up = s.rotation.col(0);
  EXPECT_TRUE(FailsWith([&] { InitScene(o); }, {"no ground found", "--up"}));
}

}  // namespace
}  // namespace vkr::test
