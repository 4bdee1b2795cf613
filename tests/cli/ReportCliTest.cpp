// report.html (docs/guide/REPORT.md) as a user meets it: every run writes it with an
// overlay per camera; `vkrecon report` rebuilds it byte for byte from the folder; without the
// JavaScript packages it still writes and says what it left out; a folder that is not a
// run's is bad input; and headless Chromium finds no error in the page.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
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
const fs::path kChartJs = "/usr/share/javascript/chart.js/chart.min.js";

// One small run of the box (160×120, atlas 64, 60 iterations), shared by the tests below.
class ReportCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<test::TempDir>();
    const test::TempDir& dir = *dir_;
    synth_ = RunCommand(kVkrecon + " synth -q " + Quote(kBox / "scene.json") + " --at " + Quote(kBox / "truth.json") +
                        " --scale 0.25 --noise 8 -o " + Quote(dir / "images"));
    if (synth_.exit_status != 0) return;
    run_ = RunCommand(kVkrecon + " run -q " + Quote(kBox / "scene.json") + " --set cameras=" +
                      Quote(dir / "images/cameras.json") + " --set images=" + Quote(dir / "images") +
                      " --set likelihood.atlas=64 --set likelihood.levels=2 --set sampler.iterations=60"
                      " --set sampler.chains=2 --set sampler.batch=4 -o " + Quote(dir / "run"));
  }
  static void TearDownTestSuite() { dir_.reset(); }
  void SetUp() override {
    ASSERT_EQ(synth_.exit_status, 0) << synth_.err;
    // Exit 1 is a verdict of the (deliberately short) run, not a failure to write its outputs.
    ASSERT_TRUE(run_.exit_status == 0 || run_.exit_status == 1) << run_.err;
    ASSERT_TRUE(fs::exists(out() / "map.json")) << run_.err;
  }
  static fs::path out() { return *dir_ / "run"; }
  static nlohmann::json Map() { return nlohmann::json::parse(test::ReadText(out() / "map.json")); }

  static std::unique_ptr<test::TempDir> dir_;
  static test::CommandResult synth_, run_;
};
std::unique_ptr<test::TempDir> ReportCli::dir_;
test::CommandResult ReportCli::synth_, ReportCli::run_;

TEST_F(ReportCli, RunWritesTheReportAndAnOverlayPerCamera) {
  const fs::path html_file = out() / "report.html";
  ASSERT_TRUE(fs::exists(html_file));
  EXPECT_LT(fs::file_size(html_file), 5u * 1024 * 1024);
  const std::string html = test::ReadText(html_file);
  const nlohmann::json map = Map();
  for (const auto& [name, value] : map["parameters"].items())
    EXPECT_NE(html.find("<td class=\"name\">" + name + "</td>"), std::string::npos) << name;
  const std::string verdict = map["diagnosis"]["verdict"].get<std::string>();
  EXPECT_NE(html.find("diagnosis: <b>" + verdict + "</b>"), std::string::npos) << verdict;
  EXPECT_NE(html.find("id=\"report-errors\""), std::string::npos);
  // Which κ the intervals are stated at, in map.json and on the page: the noise's where the
  // diagnosis finds no model error, a factor √(κ_noise/κ) of the chains' spread.
  const nlohmann::json& calibration = map["calibration"];
  ASSERT_TRUE(calibration.contains("intervals")) << calibration.dump();
  const nlohmann::json& intervals = calibration["intervals"];
  const double kappa_noise = calibration["noise_correlation"]["kappa"].get<double>();
  EXPECT_GE(kappa_noise, 1.0);
  if (verdict == "model_error" || verdict == "failed") {
    EXPECT_EQ(intervals["from"], "sandwich");
    EXPECT_EQ(intervals["scale"], 1.0);
  } else {
    EXPECT_EQ(intervals["from"], "noise") << intervals.dump();
    EXPECT_DOUBLE_EQ(intervals["kappa"].get<double>(), kappa_noise);
    EXPECT_NEAR(intervals["scale"].get<double>(), std::sqrt(kappa_noise / calibration["kappa"].get<double>()), 1e-9);
  }
  EXPECT_NE(html.find("intervals at κ"), std::string::npos);
  const nlohmann::json cameras = map["diagnosis"]["cameras"];
  ASSERT_FALSE(cameras.empty());
  for (const auto& c : cameras) {
    const std::string name = c["camera"].get<std::string>();
    EXPECT_TRUE(fs::exists(out() / "overlays" / (name + ".png"))) << name;
    EXPECT_NE(html.find("<h3>" + name + "</h3>"), std::string::npos) << name;
  }
  // Nothing to fetch: no external script, style sheet or image (the libraries' own texts
  // mention URLs, so look at the attributes that would load one).
  for (const char* fetch : {"src=\"http", "href=\"http", "src=\"//", "<link"})
    EXPECT_EQ(html.find(fetch), std::string::npos) << fetch << ": the page must open without a network";
  if (!fs::exists(kChartJs)) GTEST_SKIP() << kChartJs << " is not installed (Debian: libjs-chart.js): not checked that "
                                                         "the report inlines Chart.js";
  EXPECT_NE(html.find("Chart.js v"), std::string::npos) << "Chart.js is installed but not inlined";
  EXPECT_NE(html.find("data-report-charts"), std::string::npos);
}

TEST_F(ReportCli, ReportCommandRebuildsTheSameFile) {
  const std::string before = test::ReadText(out() / "report.html");
  fs::remove(out() / "report.html");
  const auto r = RunCommand(kVkrecon + " report -q " + Quote(out()));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  EXPECT_TRUE(test::ReadText(out() / "report.html") == before) << "vkrecon report wrote another page than the run";
}

TEST_F(ReportCli, WithoutTheLibrariesTheReportSaysWhatItLeftOut) {
  test::TempDir copy;
  fs::copy(out(), copy.path(), fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  const auto r = RunCommand("VKRECON_JAVASCRIPT_DIR=" + Quote(copy / "no-js") + " " + kVkrecon + " report " +
                            Quote(copy.path()) + " --truth " + Quote(kBox / "truth.json"));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  EXPECT_NE(r.err.find("libjs-chart.js"), std::string::npos) << r.err;
  const std::string html = test::ReadText(copy / "report.html");
  EXPECT_NE(html.find("Left out of this page"), std::string::npos);
  EXPECT_NE(html.find("libjs-chart.js"), std::string::npos);
  EXPECT_NE(html.find("libjs-three"), std::string::npos);
  EXPECT_EQ(html.find("Chart.js v"), std::string::npos);
  EXPECT_NE(html.find("<th>truth</th>"), std::string::npos);  // --truth adds the column
  EXPECT_NE(html.find("<td class=\"name\">yaw</td>"), std::string::npos);
}

TEST_F(ReportCli, BrowserFindsNoErrorInThePage) {
  const fs::path shot = *dir_ / "report.png";
  const auto r = RunCommand(Quote(fs::path(VKRECON_SOURCE_DIR) / "scripts/report_screenshot.sh") + " " +
                            Quote(out() / "report.html") + " " + Quote(shot));
  if (r.exit_status == 77) GTEST_SKIP() << "chromium is not installed (scripts/bootstrap.sh report): " << r.err;
  EXPECT_EQ(r.exit_status, 0) << r.err;
  EXPECT_TRUE(fs::exists(shot));
}

TEST(ReportCliInput, FolderWithoutMapJsonIsBadInput) {
  test::TempDir dir;
  const auto r = RunCommand(kVkrecon + " report " + Quote(dir.path()));
  test::ExpectBadInput(r, {(dir / "map.json").string(), "missing"});
}

TEST(ReportCliInput, MalformedChainIsBadInput) {
  test::TempDir dir;
  test::WriteText(dir / "map.json", R"({"parameters": {"x": {"map": 1}}, "settings": {}})");
  test::WriteText(dir / "chain.csv", "iteration,chain\n0,0\n");
  const auto r = RunCommand(kVkrecon + " report " + Quote(dir.path()));
  test::ExpectBadInput(r, {(dir / "chain.csv").string(), "header"});
}

// map.json and chain.csv alone (no images, no model, a scene that no longer exists): the page
// is still written, and says what it could not show; a --truth file that is missing is bad input.
TEST(ReportCliInput, BareFolderStillGivesAPageAndAMissingTruthIsBadInput) {
  test::TempDir dir;
  test::WriteText(dir / "map.json", R"({"parameters": {"x": {"map": 1, "mean": 1, "sd": 0.1, "q025": 0.8,
    "q975": 1.2, "ess": 500, "rhat": 1.0}}, "settings": {"scene": "/nonexistent/scene.json"}, "burn_in": 1})");
  test::WriteText(dir / "chain.csv",
                  "iteration,chain,level,temperature,accepted,swapped,log_posterior,log_likelihood,log_prior,x\n"
                  "0,0,0,1,1,0,-1,-1,0,0.9\n1,0,0,1,0,0,-1,-1,0,1.1\n2,0,0,1,1,0,-1,-1,0,1.0\n");
  const auto r = RunCommand(kVkrecon + " report -q " + Quote(dir.path()));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const std::string html = test::ReadText(dir / "report.html");
  EXPECT_NE(html.find("<td class=\"name\">x</td>"), std::string::npos);
  EXPECT_NE(html.find("the scene cannot be read now"), std::string::npos);
  EXPECT_NE(html.find("model.glb is missing"), std::string::npos);
  test::ExpectBadInput(RunCommand(kVkrecon + " report " + Quote(dir.path()) + " --truth " + Quote(dir / "truth.json")),
                       {(dir / "truth.json").string(), "missing"});
}

}  // namespace
}  // namespace vkr
