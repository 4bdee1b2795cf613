// The image-space likelihood's contracts: pair selection, calibration of the noise model at
// the truth, the counts, batch independence, levels, the dump agreeing with the reduction,
// and the errors.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "engine/common/InputError.h"
#include "pipelines/likelihood/ImageLikelihood.h"
#include "pipelines/passes/TargetWarpPass.h"
#include "pipelines/rendering/ViewRendering.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;

constexpr double kSigma = 16.0;

// The box asset at quarter size (160×120, 9 cameras, 72 ordered pairs) with noisy images
// at the truth, made once for the suite.
class ImageLikelihoodBox : public test::GpuTest {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir;
    const fs::path root = fs::path(VKRECON_SOURCE_DIR) / "assets/box";
    SynthOptions synth;
    synth.scene_file = root / "scene.json";
    synth.at_file = root / "truth.json";
    synth.output_dir = dir_->path();
    synth.noise_sigma = kSigma;
    synth.seed = 11;
    synth.scale = 0.25;
    synth.atlas = 1024;
    SynthesiseImages(synth, device());
    scene_ = new Scene(LoadScene(root / "scene.json", {{"cameras", (*dir_ / "cameras.json").string()},
                                                       {"images", dir_->path().string()}}));
    truth_ = scene_->ValuesFromFile(root / "truth.json");
  }
  static void TearDownTestSuite() {
    delete scene_;
    delete dir_;
    scene_ = nullptr;
    dir_ = nullptr;
  }
  static ImageLikelihoodOptions Options() {
    ImageLikelihoodOptions o = ImageLikelihoodOptions::FromScene(*scene_);
    o.model.sigma = kSigma;
    o.levels = 2;
    o.max_batch = 4;
    return o;
  }
  static double Chi2PerDof(const Evaluation& e) {
    const double sigma = kSigma / 255.0;
    return e.scalars.sum_squares / (sigma * sigma) / e.scalars.dof;
  }
  static test::TempDir* dir_;
  static Scene* scene_;
  static std::vector<double> truth_;
};
test::TempDir* ImageLikelihoodBox::dir_ = nullptr;
Scene* ImageLikelihoodBox::scene_ = nullptr;
std::vector<double> ImageLikelihoodBox::truth_;

bool SameScalars(const ReducedScalars& a, const ReducedScalars& b) {
  return std::memcmp(&a.sum_squares, &b.sum_squares, sizeof(double)) == 0 && a.dof == b.dof &&
         a.seen_multi == b.seen_multi && a.seen_once == b.seen_once && a.seen_none == b.seen_none &&
         a.interior == b.interior;
}

TEST(ImageLikelihoodPairs, AllOrderedPairsOrNearestPartners) {
  // Four cameras on a line along x, looking down +z except the last, which looks along +x.
  std::vector<Camera> cameras(4);
  cameras[3].cam_from_world.topLeftCorner<3, 3>() << 0, 0, -1, 0, 1, 0, 1, 0, 0;
  for (int i = 0; i < 4; ++i)  // centres at x = 0, 1, 4, 9
    cameras[i].cam_from_world.topRightCorner<3, 1>() = -cameras[i].R() * Eigen::Vector3d(i * i, 0, 0);
  const std::vector<CameraPair> all = SelectPairs(cameras, 0, PartnerRanking::Distance);
  ASSERT_EQ(all.size(), 12u);
  EXPECT_EQ(all[0], (CameraPair{1, 0}));
  EXPECT_EQ(all[2], (CameraPair{3, 0}));
  EXPECT_EQ(all[3], (CameraPair{0, 1}));
  EXPECT_EQ(SelectPairs(cameras, 3, PartnerRanking::Distance), all);
  // Nearest centres: camera 2 (at x = 4) pairs with 1 (x = 1) and 0 (x = 0) before 3 (x = 9).
  const std::vector<CameraPair> near = SelectPairs(cameras, 2, PartnerRanking::Distance);
  ASSERT_EQ(near.size(), 8u);
  EXPECT_EQ(near[4], (CameraPair{0, 2}));
  EXPECT_EQ(near[5], (CameraPair{1, 2}));
  EXPECT_EQ(near[6], (CameraPair{1, 3}));
  EXPECT_EQ(near[7], (CameraPair{2, 3}));
  // Viewing directions: camera 3 looks elsewhere, so nobody's single best partner is 3.
  for (const CameraPair& p : SelectPairs(cameras, 1, PartnerRanking::Direction)) {
    if (p.target != 3) EXPECT_NE(p.source, 3);
    EXPECT_NE(p.source, p.target);
  }
  PartnerRanking r;
  EXPECT_TRUE(FromString(ToString(PartnerRanking::Direction), &r));
  EXPECT_EQ(r, PartnerRanking::Direction);
  EXPECT_FALSE(FromString("closest", &r));
}

TEST_F(ImageLikelihoodBox, CalibratedAtTheTruth) {
  ImageLikelihood likelihood(device(), *scene_, Options());
  EXPECT_EQ(likelihood.pairs().size(), 72u);
  const Evaluation e = likelihood.Evaluate({truth_})[0];
  const ReducedScalars& s = e.scalars;
  // Every pair compares thousands of pixels; some surface t sees is hidden from s.
  EXPECT_GT(s.seen_multi, 72u * 5000u);
  EXPECT_GT(s.seen_once, 10000u);
  EXPECT_EQ(s.seen_none, 0u);
  EXPECT_EQ(s.interior, 0u);
  EXPECT_EQ(s.dof, 3.0 * s.seen_multi);
  EXPECT_EQ(e.log_occlusion_prior, 0.0);
  // Noise σ in both images: χ²/dof near 1. (Below 1 with the position term δ = 0.5: the
  // synthetic images are registered exactly, so that allowance goes unused.)
  EXPECT_GT(Chi2PerDof(e), 0.8);
  EXPECT_LT(Chi2PerDof(e), 1.05);
  ImageLikelihoodOptions no_position = Options();
  no_position.position_sd = 0.0;
  const Evaluation raw = ImageLikelihood(device(), *scene_, no_position).Evaluate({truth_})[0];
  EXPECT_GT(Chi2PerDof(raw), 0.95);
  EXPECT_LT(Chi2PerDof(raw), 1.15);
}

TEST_F(ImageLikelihoodBox, BatchPositionDoesNotChangeTheResult) {
  ImageLikelihood likelihood(device(), *scene_, Options());
  std::vector<double> wrong = truth_;
  wrong[0] += 0.1;  // x
  const std::vector<Evaluation> batch = likelihood.Evaluate({wrong, truth_, wrong, truth_});
  const Evaluation single = likelihood.Evaluate({truth_})[0];
  EXPECT_TRUE(SameScalars(batch[1].scalars, single.scalars));
  EXPECT_TRUE(SameScalars(batch[3].scalars, single.scalars));
  EXPECT_TRUE(SameScalars(batch[0].scalars, batch[2].scalars));
  EXPECT_GT(single.total(), batch[0].total() + 1000.0);
  EXPECT_THROW(likelihood.Evaluate(std::vector<std::vector<double>>(5, truth_)), std::invalid_argument);
  EXPECT_THROW(likelihood.Evaluate({{0.0}}), std::invalid_argument);
}

TEST_F(ImageLikelihoodBox, LevelsAndPartners) {
  ImageLikelihood likelihood(device(), *scene_, Options());
  const Evaluation fine = likelihood.Evaluate({truth_})[0];
  likelihood.SetLevel(1);
  EXPECT_EQ(likelihood.level(), 1);
  const Evaluation coarse = likelihood.Evaluate({truth_})[0];
  // A level has a quarter of the pixels.
  EXPECT_NEAR(double(coarse.scalars.seen_multi) / fine.scalars.seen_multi, 0.25, 0.02);
  EXPECT_THROW(likelihood.SetLevel(2), std::out_of_range);
  EXPECT_THROW(likelihood.SetLevel(-1), std::out_of_range);

  ImageLikelihoodOptions two = Options();
  two.partners = 2;
  ImageLikelihood nearest(device(), *scene_, two);
  EXPECT_EQ(nearest.pairs().size(), 18u);
  const Evaluation e = nearest.Evaluate({truth_})[0];
  EXPECT_LT(e.scalars.seen_multi, fine.scalars.seen_multi / 3);
  // Neighbours on the ring see the scene alike: proportionally more of t's surface is in s.
  EXPECT_LT(double(e.scalars.seen_once) / e.scalars.seen_multi,
            double(fine.scalars.seen_once) / fine.scalars.seen_multi);
}

// The dump draws every pair alone (one source per draw); the evaluation draws each target
// with up to TargetWarpPass::kMaxSources sources at once and sums them per pixel. Both must
// count the same pixel pairs and agree on Σχ² to float rounding.
void ExpectDumpAgreesWithTheReduction(ImageLikelihood& likelihood, const std::vector<double>& psi) {
  const Scene& scene = likelihood.scene();
  Evaluation e;
  const ImageDump dump = likelihood.EvaluateAndDump(psi, &e);
  ASSERT_EQ(dump.pairs.size(), likelihood.pairs().size());
  double chi2 = 0.0;
  uint32_t compared = 0, once = 0;
  for (const ImagePairDump& d : dump.pairs) {
    const Camera t = scene.Cameras(psi)[size_t(d.pair.target)];
    ASSERT_EQ(d.synthetic.width, t.width);
    ASSERT_EQ(d.consistency.height, t.height);
    int holes = 0, surface = 0;
    for (int y = 0; y < t.height; ++y)
      for (int x = 0; x < t.width; ++x) {
        const float* c = d.consistency.At(x, y);
        const float* s = d.synthetic.At(x, y);
        ASSERT_EQ(s[3] > 0.5f, c[1] > 0.0f) << "synthetic alpha marks the compared pixels";
        if (c[1] > 0.0f) {
          chi2 += c[0];
          ++compared;
        } else if (c[3] > 0.5f) {
          ++once;
        }
        surface += c[3] > 0.5f;
        // The depth-equal test shades every visible pixel: no holes in t's surface.
        if (x > 0 && y > 0 && x + 1 < t.width && y + 1 < t.height && c[3] < 0.5f)
          holes += d.consistency.At(x - 1, y)[3] > 0.5f && d.consistency.At(x + 1, y)[3] > 0.5f &&
                   d.consistency.At(x, y - 1)[3] > 0.5f && d.consistency.At(x, y + 1)[3] > 0.5f;
      }
    // (A pixel on a silhouette may show the back of a face, which counts as no surface.)
    EXPECT_GT(surface, t.width * t.height / 2) << "the ground fills most of every view";
    EXPECT_LE(holes, 2) << "pair " << d.pair.source << "→" << d.pair.target;
  }
  const double sigma = likelihood.options().model.sigma / 255.0;
  EXPECT_EQ(compared, e.scalars.seen_multi);
  EXPECT_EQ(once, e.scalars.seen_once);
  EXPECT_NEAR(chi2 * sigma * sigma, e.scalars.sum_squares, 1e-5 * e.scalars.sum_squares);
  // The same hypothesis without a dump evaluates identically.
  EXPECT_TRUE(SameScalars(likelihood.Evaluate({psi})[0].scalars, e.scalars));
}

TEST_F(ImageLikelihoodBox, DumpAgreesWithTheReduction) {
  ImageLikelihoodOptions o = Options();
  o.partners = 2;
  ImageLikelihood nearest(device(), *scene_, o);
  ExpectDumpAgreesWithTheReduction(nearest, truth_);
  // All 8 sources of each target in one draw, at the truth and off it.
  ImageLikelihood all(device(), *scene_, Options());
  ExpectDumpAgreesWithTheReduction(all, truth_);
  std::vector<double> wrong = truth_;
  wrong[0] += 0.1;  // x
  ExpectDumpAgreesWithTheReduction(all, wrong);
}

TEST_F(ImageLikelihoodBox, MoreSourcesThanOneDrawTakes) {
  // 12 cameras (the 9 and copies of the first 3 under other names): each target has 11
  // sources, more than TargetWarpPass::kMaxSources, so its pairs take two draws.
  nlohmann::json cameras = nlohmann::json::parse(std::ifstream(*dir_ / "cameras.json"));
  nlohmann::json& list = cameras["cameras"];
  for (int i = 0; i < 3; ++i) {
    nlohmann::json copy = list[size_t(i)];
    copy["name"] = copy["name"].get<std::string>() + "_again";
    list.push_back(copy);
  }
  ASSERT_GT(int(list.size()) - 1, TargetWarpPass::kMaxSources);
  std::ofstream(*dir_ / "cameras12.json") << cameras.dump();
  const Scene twelve = LoadScene(fs::path(VKRECON_SOURCE_DIR) / "assets/box/scene.json",
                                 {{"cameras", (*dir_ / "cameras12.json").string()}, {"images", dir_->path().string()}});
  ImageLikelihoodOptions o = Options();
  o.max_batch = 2;
  ImageLikelihood likelihood(device(), twelve, o);
  EXPECT_EQ(likelihood.pairs().size(), 132u);
  ExpectDumpAgreesWithTheReduction(likelihood, truth_);
  // A camera and its copy see alike: their pairs compare almost every pixel, at a χ² near 0
  // (the same noisy image on both sides), so the 12 cameras' χ²/dof is below the 9's.
  const Evaluation nine = ImageLikelihood(device(), *scene_, Options()).Evaluate({truth_})[0];
  const Evaluation e = likelihood.Evaluate({truth_})[0];
  EXPECT_GT(e.scalars.seen_multi, nine.scalars.seen_multi);
  EXPECT_LT(Chi2PerDof(e), Chi2PerDof(nine));
}

TEST_F(ImageLikelihoodBox, ProfileTimesEveryPass) {
  ImageLikelihoodOptions o = Options();
  o.profile = true;
  o.partners = 1;
  ImageLikelihood likelihood(device(), *scene_, o);
  EXPECT_TRUE(likelihood.LastPassTimesMs().empty());
  likelihood.Evaluate({truth_, truth_});
  const auto times = likelihood.LastPassTimesMs();
  for (const char* pass : {"depth", "warp", "compare", "reduce"}) {
    ASSERT_TRUE(times.count(pass)) << pass;
    EXPECT_GE(times.at(pass), 0.0) << pass;
  }
}

TEST_F(ImageLikelihoodBox, BadOptionsAndScenes) {
  ImageLikelihoodOptions o = Options();
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  o.partners = -1;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_THROW(ImageLikelihood(device(), *scene_, o), std::invalid_argument);
  o = Options();
  o.model.sigma = 0.0;
  EXPECT_FALSE(o.IsValid(&why));
  o = Options();
  o.levels = 8;  // 160×120 has mips down to 10×7 only
  EXPECT_THROW(ImageLikelihood(device(), *scene_, o), InputError);
  // The scene's likelihood.partners: at most the other cameras (8).
  auto with_partners = [&](const std::string& k) {
    return LoadScene(fs::path(VKRECON_SOURCE_DIR) / "assets/box/scene.json",
                     {{"cameras", (*dir_ / "cameras.json").string()},
                      {"images", dir_->path().string()},
                      {"likelihood.partners", k},
                      {"likelihood.partner_ranking", "direction"}});
  };
  const ImageLikelihoodOptions eight = ImageLikelihoodOptions::FromScene(with_partners("8"));
  EXPECT_EQ(eight.partners, 8);
  EXPECT_EQ(eight.ranking, PartnerRanking::Direction);
  try {
    ImageLikelihoodOptions::FromScene(with_partners("9"));
    ADD_FAILURE() << "9 partners of 9 cameras";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("likelihood.partners"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vkr
