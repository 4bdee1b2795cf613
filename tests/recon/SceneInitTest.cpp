// `vkrecon init` (recon/SceneInit.h) on COLMAP models synthesised from the bundled assets: the
// ground and up within 1° of the truth's, the cameras the truth's up to a turn about z and a
// shift along the ground, the starter scene's priors around the truth; and bad input refused.

#include "recon/SceneInit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "tests/recon/SyntheticColmap.h"
#include "tests/scene/SceneTestUtil.h"

namespace vkr::test {
namespace {

using recon::InitOptions;
using recon::InitScene;
using recon::InitTemplate;

// X_scene = Rz(yaw) · X_truth + (shift, 0): what init leaves free once the ground is z = 0 and
// the scale is known. Fitted to the camera centres (2D Procrustes).
struct FreeMotion {
  double yaw = 0.0;  // radians
  Eigen::Vector2d shift = Eigen::Vector2d::Zero();
  Eigen::Vector2d Apply(const Eigen::Vector2d& p) const { return Eigen::Rotation2Dd(yaw) * p + shift; }
};

FreeMotion FitFreeMotion(const std::vector<Camera>& truth, const std::vector<Camera>& scene) {
  Eigen::Vector2d mt = Eigen::Vector2d::Zero(), ms = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < truth.size(); ++i) mt += truth[i].Centre().head<2>(), ms += scene[i].Centre().head<2>();
  mt /= double(truth.size()), ms /= double(truth.size());
  double dot = 0.0, cross = 0.0;
  for (size_t i = 0; i < truth.size(); ++i) {
    const Eigen::Vector2d a = truth[i].Centre().head<2>() - mt, b = scene[i].Centre().head<2>() - ms;
    dot += a.dot(b), cross += a.x() * b.y() - a.y() * b.x();
  }
  FreeMotion m;
  m.yaw = std::atan2(cross, dot);
  m.shift = ms - Eigen::Rotation2Dd(m.yaw) * mt;
  return m;
}

// The truth's footprint parameters in the scene frame. A box's yaw is the same modulo 90° with w
// and d swapped; a house's only modulo 180°, stairs' (the way up) modulo 360°.
std::map<std::string, double> TruthInScene(const SyntheticColmap& s, const FreeMotion& m, InitTemplate kind) {
  const bool box = kind == InitTemplate::Box;
  std::map<std::string, double> v;
  for (size_t i = 0; i < s.scene.parameters.size(); ++i) v[s.scene.parameters[i].name] = s.truth[i];
  // house_cloth's origin is its front wall's middle (its walls are translated by d/2 along
  // their own y); the templates' is the walls' centre.
  if (v.count("wl")) {  // house_cloth, the one asset with a wing
    const double yaw = v["yaw"] * M_PI / 180.0;
    v["x"] -= std::sin(yaw) * v["d"] / 2, v["y"] += std::cos(yaw) * v["d"] / 2;
  }
  const Eigen::Vector2d xy = m.Apply({v["x"], v["y"]});
  v["x"] = xy.x(), v["y"] = xy.y();
  double yaw = std::remainder(v["yaw"] + m.yaw * 180.0 / M_PI, kind == InitTemplate::Stairs ? 360.0 : 180.0);
  if (box && std::abs(yaw) > 45.0) yaw -= std::copysign(90.0, yaw), std::swap(v["w"], v["d"]);
  v["yaw"] = yaw;
  return v;
}

struct AssetCase {
  const char* asset;
  InitTemplate kind;
  bool binary;
  std::uint64_t seed;
  bool background = false;  // a building and trees behind the object, as real photographs have
};

void PrintTo(const AssetCase& c, std::ostream* os) {
  *os << c.asset << (c.binary ? " binary" : " text") << " seed " << c.seed << (c.background ? " background" : "");
}

// 400 points on a wall 8 m wide and 3 m tall 9 m from the object and on three trees 2–3 m tall.
void AddBackground(const SyntheticColmap& s) {
  RewriteColmap(s, [&](ColmapReconstruction& m) {
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 400; ++i) {
      Eigen::Vector3d truth(9.0, 8.0 * unit(rng) - 4.0, 3.0 * unit(rng));
      if (i % 2) {
        const double tree = double(i % 3), angle = 2.0 + tree, r = 0.6 * unit(rng);
        truth = Eigen::Vector3d(7.0 * std::cos(angle) + r * std::cos(7.0 * i), 7.0 * std::sin(angle) + r * std::sin(7.0 * i),
                                1.0 + 1.5 * unit(rng) + tree * 0.3);
      }
      ColmapPoint p;
      p.id = 900000 + i;
      p.xyz = s.scale * (s.rotation * truth) + s.translation;
      m.points.push_back(p);
    }
  });
}

class InitOnAsset : public ::testing::TestWithParam<AssetCase> {};

TEST_P(InitOnAsset, GroundCamerasAndPriors) {
  const AssetCase& c = GetParam();
  TempDir dir;
  const SyntheticColmap s = MakeSyntheticColmap(c.asset, dir.path(), c.binary, c.seed);
  if (c.background) AddBackground(s);
  const bool masks = c.seed % 2 == 1;  // COLMAP's project/masks beside project/images
  if (masks) std::filesystem::create_directories(dir / "masks");
  InitOptions o;
  o.sparse = s.sparse;
  o.output = dir / "scene";
  o.template_kind = c.kind;
  o.scale = recon::ScalePoints{s.far_a, s.far_b, s.far_metres};
  const recon::InitResult r = InitScene(o);
  const double up_error = std::acos(std::min(1.0, r.up.dot(s.rotation.col(2)))) * 180.0 / M_PI;
  std::cout << c.asset << ": ground normal " << up_error << "° from the truth's up; scale error "
            << r.scale * s.scale - 1.0 << "\n" << r.BriefReport();
  EXPECT_LT(up_error, 1.0);
  EXPECT_NEAR(r.scale * s.scale, 1.0, 1e-3);

  const Scene scene = LoadScene(dir / "scene/scene.json");  // the photographs resolve and fit
  const std::vector<Camera> cameras = scene.Cameras(scene.InitialValues());
  const std::string scene_json = ReadText(dir / "scene/scene.json");
  EXPECT_NE(scene_json.find("\"images\": \"../images/\""), std::string::npos) << scene_json;
  EXPECT_EQ(scene_json.find("\"masks\": \"../masks/\"") != std::string::npos, masks) << scene_json;
  ASSERT_EQ(cameras.size(), s.cameras.size());
  const FreeMotion m = FitFreeMotion(s.cameras, cameras);
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(m.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (size_t i = 0; i < cameras.size(); ++i) {
    const Eigen::Vector3d truth = s.cameras[i].Centre(), got = cameras[i].Centre();
    EXPECT_LT((m.Apply(truth.head<2>()) - got.head<2>()).norm(), 0.02) << cameras[i].name;
    EXPECT_NEAR(got.z(), truth.z(), 0.02) << cameras[i].name;
    EXPECT_LT((cameras[i].R() - s.cameras[i].R() * turn.transpose()).norm(), 0.03) << cameras[i].name;
    EXPECT_EQ(cameras[i].K, s.cameras[i].K);
  }

  const std::map<std::string, double> truth = TruthInScene(s, m, c.kind);
  for (const Parameter& p : scene.parameters) {
    ASSERT_TRUE(truth.count(p.name)) << p.name;
    const double v = truth.at(p.name);
    EXPECT_TRUE(p.prior.a <= v && v <= p.prior.b) << p.name << " = " << v << " outside [" << p.prior.a << ", " << p.prior.b << "]";
  }
  const std::string vertices = c.background ? "3400" : "3000";
  EXPECT_NE(ReadText(dir / "scene/points.ply").find("element vertex " + vertices + "\n"), std::string::npos);
}

// A ground is weak when it leans far from how the photographs were held or stands on few
// points, not because a building's ground holds a small share of them (Merton: 5 %).
TEST(InitReport, WarnsOfAWeakGroundOnlyWhenItLeansOrHasFewPoints) {
  recon::InitResult r;
  r.points = 2627, r.ground_inliers = 133, r.up_vs_cameras_deg = 3.0;
  EXPECT_EQ(r.BriefReport().find("weak ground"), std::string::npos) << r.BriefReport();
  r.ground_inliers = 40;
  EXPECT_NE(r.BriefReport().find("warning: a weak ground"), std::string::npos);
  r.ground_inliers = 133, r.up_vs_cameras_deg = 25.0;
  EXPECT_NE(r.BriefReport().find("warning: a weak ground"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(Assets, InitOnAsset,
                         ::testing::Values(AssetCase{"box", InitTemplate::Box, false, 1},
                                           AssetCase{"box", InitTemplate::Box, true, 2},
                                           AssetCase{"house", InitTemplate::House, false, 3},
                                           AssetCase{"house", InitTemplate::House, true, 4},
                                           AssetCase{"focal", InitTemplate::Box, true, 5},
                                           AssetCase{"crate_clutter", InitTemplate::Box, false, 6},
                                           AssetCase{"box", InitTemplate::Box, true, 7, true},
                                           AssetCase{"house", InitTemplate::House, false, 8, true},
                                           AssetCase{"house_annex", InitTemplate::House, true, 9},
                                           AssetCase{"house_cloth", InitTemplate::House, false, 13},
                                           AssetCase{"poster", InitTemplate::Cylinder, false, 10},
                                           AssetCase{"stairs", InitTemplate::Stairs, true, 11},
                                           AssetCase{"stairs", InitTemplate::Stairs, false, 12}),
                         [](const auto& info) {
                           return std::string(info.param.asset) + (info.param.binary ? "_binary" : "_text") +
                                  (info.param.background ? "_background" : "");
                         });

}  // namespace
}  // namespace vkr::test
