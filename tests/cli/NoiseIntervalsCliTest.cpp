// The intervals `vkrecon run` states (recon/NoiseIntervals.h), as a user meets them: on
// photographs the box explains, the chains sample at the sandwich's κ and map.json states the
// intervals at the noise's, the same chains' spread about the MAP times √(κ_noise/κ); with
// `likelihood.kappa: "sandwich"` the same run states the chains' spread as it is.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "tests/cli/CliTestUtil.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;
using test::Quote;
using test::RunCommand;

const std::string kVkrecon = VKRECON_BINARY;
const fs::path kBox = fs::path(VKRECON_SOURCE_DIR) / "assets/box";

// Half-size photographs at σ 16, a 128² atlas and 60 iterations: about 20 s on lavapipe, and
// residuals the diagnosis takes for noise (the quarter-size box's it does not).
nlohmann::json RunBox(const test::TempDir& dir, const std::string& name, const std::string& kappa) {
  const auto r = RunCommand(kVkrecon + " run -q " + Quote(kBox / "scene.json") + " --set cameras=" +
                            Quote(dir / "images/cameras.json") + " --set images=" + Quote(dir / "images") +
                            " --set likelihood.atlas=128 --set sampler.iterations=60 --set likelihood.kappa=" + kappa +
                            " -o " + Quote(dir / name));
  EXPECT_TRUE(r.exit_status == 0 || r.exit_status == 1) << r.err;
  return nlohmann::json::parse(test::ReadText(dir / name / "map.json"));
}

TEST(NoiseIntervalsCli, TheSameChainsStatedAtTheNoisesKappa) {
  test::TempDir dir;
  ASSERT_EQ(RunCommand(kVkrecon + " synth -q " + Quote(kBox / "scene.json") + " --at " + Quote(kBox / "truth.json") +
                       " --scale 0.5 --noise 16 --seed 1 -o " + Quote(dir / "images"))
                .exit_status,
            0);
  const nlohmann::json stated = RunBox(dir, "auto", "auto");
  const nlohmann::json sampled = RunBox(dir, "sandwich", "sandwich");
  ASSERT_NE(stated["diagnosis"]["verdict"], "model_error") << stated["diagnosis"].dump();
  const nlohmann::json& intervals = stated["calibration"]["intervals"];
  ASSERT_EQ(intervals["from"], "noise") << intervals.dump();
  const double kappa = stated["calibration"]["kappa"].get<double>();
  const double kappa_noise = stated["calibration"]["noise_correlation"]["kappa"].get<double>();
  EXPECT_GT(kappa_noise, 1.5);  // neighbouring texels share pixels
  EXPECT_LT(kappa_noise, kappa);
  const double scale = intervals["scale"].get<double>();
  EXPECT_NEAR(scale, std::sqrt(kappa_noise / kappa), 1e-9);
  EXPECT_EQ(sampled["calibration"]["intervals"]["from"], "sandwich");
  EXPECT_EQ(sampled["calibration"]["intervals"]["scale"], 1.0);
  // The chains are the same (both sample at the sandwich's κ); only what is stated differs:
  // the spread the curvature explains shrinks by `scale`, any beyond it stays (the box's
  // priors are uniform).
  for (const auto& [name, p] : stated["parameters"].items()) {
    const nlohmann::json& q = sampled["parameters"][name];
    const double map = p["map"].get<double>();
    EXPECT_EQ(map, q["map"].get<double>()) << name;
    const double sd = q["sd"].get<double>(), laplace = q["laplace_sd"].get<double>();
    const double factor = sd > laplace ? std::sqrt(sd * sd - laplace * laplace + scale * scale * laplace * laplace) / sd
                                       : scale;
    EXPECT_LT(factor, 1.0) << name;
    EXPECT_NEAR(p["sd"].get<double>(), factor * sd, 1e-9 * sd) << name;
    for (const char* bound : {"q025", "q975"})
      EXPECT_NEAR(p[bound].get<double>() - map, factor * (q[bound].get<double>() - map), 1e-9) << name << " " << bound;
  }
}

}  // namespace
}  // namespace vkr
