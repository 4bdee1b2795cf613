// The scene file's settings blocks, read by the layers they belong to: "likelihood"
// (pipelines/model/LikelihoodSettings.h), "sampler" (optimiser/SamplerOptions.h, through
// recon/SearchSetup.h) and "synth" (pipelines/rendering/SynthSettings.h). Each bad value is
// one line naming the scene file and the field (docs/guide/SCENE_FORMAT.md, "Errors").

#include <gtest/gtest.h>

#include "pipelines/model/LikelihoodSettings.h"
#include "pipelines/rendering/SynthSettings.h"
#include "recon/SearchSetup.h"
#include "tests/scene/SceneTestUtil.h"

namespace vkr::test {
namespace {

struct Settings {
  LikelihoodSettings likelihood;
  opt::SamplerOptions sampler;
  SynthSettings synth;
};

Settings LoadAll(const std::filesystem::path& file, const std::vector<SceneOverride>& overrides = {}) {
  const Scene scene = LoadScene(file, overrides);
  return {LikelihoodSettingsOf(scene), recon::SamplerOptionsOf(scene), SynthSettingsOf(scene)};
}

::testing::AssertionResult SettingsFail(const TempDir& dir, const Json& scene, std::vector<std::string> parts,
                                        const std::vector<SceneOverride>& overrides = {}) {
  const auto file = WriteScene(dir, scene);
  parts.push_back("scene.json");
  return FailsWith([&] { LoadAll(file, overrides); }, parts);
}

TEST(SceneSettings, AsWritten) {
  TempDir dir;
  Json scene = BaseScene();
  scene["likelihood"] = Json::parse(R"({"kind": "surface", "sigma": 8.0, "weights": "angle", "atlas": 1024,
      "levels": 3, "sandwich_blocks": 32, "charts": "pixels", "kappa": 12.5, "position_sd": 0.25, "edges": true})");
  scene["sampler"] = Json::parse(R"({"iterations": 4000, "chains": 2.0, "batch": 16, "seed": 3})");  // 2.0 is 2
  scene["synth"] = Json::parse(R"({"sun": [90, 30], "supersample": 2})");
  const Settings s = LoadAll(WriteScene(dir, scene));
  EXPECT_EQ(s.likelihood.atlas, 1024);
  EXPECT_EQ(s.likelihood.sandwich_blocks, 32);
  EXPECT_EQ(s.likelihood.kappa, 12.5);
  EXPECT_EQ(s.likelihood.position_sd, 0.25);
  EXPECT_TRUE(s.likelihood.edges);
  EXPECT_EQ(s.likelihood.charts, ChartSizing::Pixels);
  EXPECT_FALSE(s.likelihood.sigma_auto);
  EXPECT_EQ(s.sampler.chains, 2);
  EXPECT_EQ(s.sampler.temperatures, 8) << "batch / chains replicas per chain";
  EXPECT_EQ(s.sampler.iterations, 4000);
  EXPECT_FALSE(s.sampler.until_converged) << "a number of iterations is exactly that many";
  EXPECT_EQ(s.sampler.seed, 3u);
  EXPECT_TRUE(s.synth.sun);
  EXPECT_EQ(s.synth.sun_elevation, 30.0);
  EXPECT_EQ(s.synth.supersample, 2);
}

// A scene without settings gets the run's defaults (docs/guide/SCENE_FORMAT.md): σ, atlas,
// levels and the length all decided from the data; one default per setting, the type's.
TEST(SceneSettings, DefaultsAreTheTypes) {
  TempDir dir;
  const Settings s = LoadAll(WriteScene(dir, BaseScene()));
  EXPECT_EQ(ToJson(s.likelihood), ToJson(LikelihoodSettings{}));
  EXPECT_EQ(opt::ToJson(s.sampler), opt::ToJson(opt::SamplerOptions{}));
  EXPECT_EQ(ToJson(s.synth), ToJson(SynthSettings{}));
  EXPECT_TRUE(s.likelihood.sigma_auto);
  EXPECT_EQ(s.likelihood.atlas, 0);
  EXPECT_EQ(s.likelihood.levels, 0);
  EXPECT_EQ(s.likelihood.sandwich_blocks, 0);  // "auto"
  EXPECT_EQ(s.likelihood.kappa_estimate, KappaEstimate::Auto);
  EXPECT_EQ(s.likelihood.partner_ranking, PartnerRanking::Distance);
  EXPECT_EQ(s.likelihood.charts, ChartSizing::Area);
  EXPECT_TRUE(s.likelihood.edges) << "the edge term is on by default";
  EXPECT_TRUE(s.sampler.until_converged);  // "iterations": "auto"
  EXPECT_EQ(s.sampler.iterations, 600);
  EXPECT_EQ(s.sampler.TimeLimit(), opt::kDefaultTimeLimit);
  EXPECT_EQ(s.sampler.temperatures * s.sampler.chains, s.sampler.batch);
}

// What map.json states (ToJson) reads back as the same settings, through a scene file.
TEST(SceneSettings, JsonRoundTrip) {
  TempDir dir;
  LikelihoodSettings l;
  l.kind = LikelihoodKind::Image;
  l.edges = false;  // the image-space likelihood has none
  l.sigma_auto = false;
  l.sigma = 3.5;
  l.weights = ViewWeights::Uniform;
  l.atlas = 512;
  l.levels = 2;
  l.charts = ChartSizing::Pixels;
  l.photometric = PhotometricModel::Gain;
  l.slot_images = SlotImages::PerSlot;
  l.clutter = false;
  l.sandwich_blocks = 16;
  l.sandwich_adjustment = SandwichAdjustment::Curvature;
  l.kappa_estimate = KappaEstimate::Noise;
  l.position_sd = 0.75;
  l.partners = 2;
  l.partner_ranking = PartnerRanking::Direction;
  ASSERT_TRUE(l.IsValid(nullptr));
  opt::SamplerOptions o;
  o.iterations = 900;
  o.until_converged = false;
  o.time_limit = 0.0;
  o.batch = 8;
  o.chains = 2;
  o.temperatures = 3;
  SynthSettings y;
  y.sun = true;
  y.sun_azimuth = 10.0;
  y.exposure = 0.2;
  Json scene = BaseScene();
  scene["likelihood"] = Json::parse(ToJson(l).dump());
  scene["sampler"] = Json::parse(opt::ToJson(o).dump());
  scene["synth"] = Json::parse(ToJson(y).dump());
  const Settings back = LoadAll(WriteScene(dir, scene));
  EXPECT_EQ(ToJson(back.likelihood), ToJson(l));
  EXPECT_EQ(opt::ToJson(back.sampler), opt::ToJson(o));
  EXPECT_EQ(ToJson(back.synth), ToJson(y));
  l.kappa = 4.0;  // a fixed κ is written instead of the estimate
  scene["likelihood"] = Json::parse(ToJson(l).dump());
  EXPECT_EQ(LoadAll(WriteScene(dir, scene)).likelihood.kappa, 4.0);
}

TEST(SceneSettings, IsValidNamesTheField) {
  std::string why;
  LikelihoodSettings l;
  l.atlas = 1000;
  EXPECT_FALSE(l.IsValid(&why));
  EXPECT_NE(why.find("likelihood.atlas"), std::string::npos) << why;
  l = {};
  l.kind = LikelihoodKind::Image;
  l.edges = true;
  EXPECT_FALSE(l.IsValid(&why));
  EXPECT_NE(why.find("likelihood.edges"), std::string::npos) << why;
  SynthSettings y;
  y.supersample = 9;
  EXPECT_FALSE(y.IsValid(&why));
  EXPECT_NE(why.find("synth.supersample"), std::string::npos) << why;
  opt::SamplerOptions o;
  o.batch = opt::kMaxSamplerBatch + 1;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("batch"), std::string::npos) << why;
}

TEST(SceneSettings, KappaIsEstimatedByTheSandwichFromTheNoiseOrFixed) {
  TempDir dir;
  Json scene = BaseScene();
  for (const char* estimate : {"noise", "sandwich", "auto"}) {
    scene["likelihood"] = Json{{"kappa", estimate}};
    const Settings s = LoadAll(WriteScene(dir, scene));
    EXPECT_STREQ(ToString(s.likelihood.kappa_estimate), estimate);
    EXPECT_EQ(s.likelihood.kappa, 0.0);
  }
  scene["likelihood"] = Json{{"kappa", 4}};
  EXPECT_EQ(LoadAll(WriteScene(dir, scene)).likelihood.kappa, 4.0);
}

TEST(SceneSettings, OverridesByDottedPath) {
  TempDir dir;
  const auto file = WriteScene(dir, BaseScene());
  const Settings plain = LoadAll(file);
  EXPECT_EQ(plain.likelihood.sigma, 8.0);
  EXPECT_EQ(plain.likelihood.kind, LikelihoodKind::Surface);
  EXPECT_EQ(plain.sampler.seed, 1u);

  // likelihood and sampler are absent from the file: overriding creates them.
  const Settings s = LoadAll(file, {{"likelihood.sigma", "4"},
                                   {"sampler.seed", "7"},
                                   {"likelihood.kind", "image"},
                                   {"sampler.batch", "32"}});
  EXPECT_EQ(s.likelihood.sigma, 4.0);
  EXPECT_FALSE(s.likelihood.sigma_auto);  // a number replaces the default "auto"
  EXPECT_EQ(s.sampler.seed, 7u);
  EXPECT_EQ(s.likelihood.kind, LikelihoodKind::Image);
  EXPECT_EQ(s.sampler.batch, 32);
  EXPECT_TRUE(s.sampler.until_converged);  // untouched defaults stay
  EXPECT_EQ(s.likelihood.atlas, 0);

  // "auto" and numbers for the length and the time limit.
  const Settings fixed = LoadAll(file, {{"sampler.iterations", "300"}, {"sampler.time_limit", "90"}});
  EXPECT_FALSE(fixed.sampler.until_converged);
  EXPECT_EQ(fixed.sampler.iterations, 300);
  EXPECT_EQ(fixed.sampler.TimeLimit(), 90.0);
  const Settings fixed_unlimited = LoadAll(file, {{"sampler.iterations", "300"}});
  EXPECT_EQ(fixed_unlimited.sampler.TimeLimit(), 0.0);  // a fixed count runs to its end
  const Settings unlimited = LoadAll(file, {{"sampler.iterations", "auto"}, {"sampler.time_limit", "none"}});
  EXPECT_TRUE(unlimited.sampler.until_converged);
  EXPECT_EQ(unlimited.sampler.TimeLimit(), 0.0);
}

TEST(SceneSettings, LaterOverridesWinAndValuesAreValidated) {
  TempDir dir;
  Json scene = BaseScene();
  scene["likelihood"] = Json{{"sigma", 2}};
  const auto file = WriteScene(dir, scene);
  EXPECT_EQ(LoadAll(file, {{"likelihood.sigma", "5"}, {"likelihood.sigma", "6"}}).likelihood.sigma,
            6.0);
  EXPECT_TRUE(FailsWith([&] { LoadAll(file, {{"likelihood.sigma", "-1"}}); },
                        {"scene.json: likelihood.sigma", "must be > 0"}));
  EXPECT_TRUE(FailsWith([&] { LoadAll(file, {{"likelihood.kind", "volume"}}); },
                        {"likelihood.kind", "unknown kind"}));
  EXPECT_TRUE(LoadAll(file, {{"likelihood.sigma", "auto"}}).likelihood.sigma_auto);
}

TEST(SceneSettings, BadValues) {
  TempDir dir;
  Json scene = BaseScene();
  scene["likelihood"] = Json{{"sigmaa", 3}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.sigmaa", "unknown key", "'sigma'"}));
  EXPECT_TRUE(SettingsFail(dir, BaseScene(), {"likelihood.sigmaa: unknown key", "set by --set"},
                           {{"likelihood.sigmaa", "4"}}));
  // Through --set a number too large for a double arrives as text.
  EXPECT_TRUE(SettingsFail(dir, BaseScene(), {"likelihood.sigma", "not finite"}, {{"likelihood.sigma", "1e999"}}));
  scene["likelihood"] = Json{{"atlas", 1000}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.atlas", "not a power of two"}));
  scene["likelihood"] = Json{{"atlas", 16384}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.atlas", "[64, 8192]"}));
  scene["likelihood"] = Json{{"sigma", -1}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.sigma", "must be > 0"}));
  scene["likelihood"] = Json{{"levels", 9}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.levels"}));
  scene["likelihood"] = Json{{"kind", "volume"}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.kind", "unknown kind 'volume'"}));
  scene["likelihood"] = Json{{"partners", -1}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.partners"}));
  scene["likelihood"] = Json{{"partners", 1.5}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.partners", "integer"}));
  scene["likelihood"] = Json{{"partner_ranking", "closest"}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.partner_ranking", "unknown ranking 'closest'"}));
  scene["likelihood"] = Json{{"charts", "texels"}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.charts", "unknown chart sizing 'texels'", "area, pixels"}));
  scene["likelihood"] = Json{{"charts", 2}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.charts"}));
  scene["likelihood"] = Json{{"slot_images", "each"}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.slot_images", "unknown value 'each'", "per_slot"}));
  scene["likelihood"] = Json{{"sandwich_blocks", 12}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.sandwich_blocks", "blocks of 12 texels", "\"auto\""}));
  scene["likelihood"] = Json{{"sandwich_blocks", 128}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.sandwich_blocks", "[8, 64]"}));
  scene["likelihood"] = Json{{"sandwich_blocks", "largest"}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.sandwich_blocks", "8, 16, 32 or 64", "'largest'"}));
  scene["likelihood"] = Json{{"sandwich_adjustment", "matrix"}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.sandwich_adjustment", "'matrix'", "magnitude, curvature"}));
  scene["likelihood"] = Json{{"kappa", 0}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.kappa", "must be > 0"}));
  scene["likelihood"] = Json{{"kappa", "estimate"}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.kappa", "'estimate'", "\"auto\"", "\"sandwich\"", "\"noise\""}));
  scene["likelihood"] = Json{{"position_sd", -0.5}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.position_sd", "[0, 10]"}));
  scene["likelihood"] = Json{{"edges", "on"}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.edges", "true or false"}));
  scene["likelihood"] = Json{{"edges", true}, {"kind", "image"}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.edges", "image-space likelihood has no edge term"}));
  scene.erase("likelihood");
  scene["synth"] = Json{{"sun", {0, 95}}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"synth.sun[1]", "must be in (0, 90]"}));
  scene["synth"] = Json{{"sun", {0}}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"synth.sun", "[azimuth, elevation]"}));
  scene["synth"] = Json{{"exposure", 1.5}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"synth.exposure", "[0, 1)"}));
  scene["synth"] = Json{{"supersample", 0}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"synth.supersample"}));
  scene["synth"] = Json{{"sunn", 1}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"synth.sunn", "unknown key", "'sun'"}));
  scene.erase("synth");
  scene["sampler"] = Json{{"chains", 0}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"sampler.chains"}));
  scene["sampler"] = Json{{"iterations", 2.5}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"sampler.iterations", "integer"}));
  scene["sampler"] = Json{{"seed", -1}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"sampler.seed"}));
  scene["sampler"] = Json{{"iterations", "forever"}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"sampler.iterations", "\"auto\"", "\"forever\""}));
  scene["sampler"] = Json{{"time_limit", -5}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"sampler.time_limit", "must be > 0"}));
  scene["sampler"] = Json{{"time_limit", "later"}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"sampler.time_limit", "\"none\""}));
  scene.erase("sampler");
  scene["likelihood"] = Json{{"atlas", "big"}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.atlas", "power of two", "\"auto\""}));
  scene["likelihood"] = Json{{"levels", "many"}};
  EXPECT_TRUE(SettingsFail(dir, scene, {"likelihood.levels", "\"auto\""}));
  scene.erase("likelihood");
}

}  // namespace
}  // namespace vkr::test
