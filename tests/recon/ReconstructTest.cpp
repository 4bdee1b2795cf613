// Reconstruct as a library call (recon/Reconstruct.h): options that cannot run are refused
// before anything starts, a stop callback stops a run at its checkpoint, and a completed run's
// summary is the map.json it wrote, which the writer over the summary writes again alike.

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "pipelines/rendering/ViewRendering.h"
#include "recon/Reconstruct.h"
#include "recon/RunOutputs.h"
#include "recon/SearchSetup.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"

namespace vkr::test {
namespace {

namespace fs = std::filesystem;
using recon::ReconstructOptions;
using recon::ReconstructSummary;

const fs::path kBox = fs::path(VKRECON_SOURCE_DIR) / "assets/box";

std::string Read(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

class Reconstruct : public GpuTest {
 protected:
  // The box photographed at its truth, small; a short run of it (as tests/cli/RunCliTest.cpp).
  ReconstructOptions ShortRun(const TempDir& dir) {
    SynthOptions synth;
    synth.scene_file = kBox / "scene.json";
    synth.at_file = kBox / "truth.json";
    synth.output_dir = dir / "images";
    synth.noise_sigma = 8.0;
    synth.scale = 0.25;
    SynthesiseImages(synth, device());
    ReconstructOptions options;
    options.scene = std::make_shared<const Scene>(recon::LoadSearchScene(
        kBox / "scene.json", {{"images", (dir / "images").string()},
                              {"cameras", (dir / "images/cameras.json").string()},
                              {"likelihood.atlas", "64"},
                              {"likelihood.levels", "2"},
                              {"sampler.iterations", "40"},
                              {"sampler.chains", "2"},
                              {"sampler.batch", "4"}}));
    options.output_dir = dir / "out";
    options.log = nullptr;
    return options;
  }
};

TEST(ReconstructOptions, IsValidSaysWhatIsMissing) {
  ReconstructOptions options;
  std::string why;
  EXPECT_FALSE(options.IsValid(&why));
  EXPECT_NE(why.find("no scene"), std::string::npos) << why;
  EXPECT_THROW(
      {
        ReconstructSummary summary;
        recon::Reconstruct(options, GpuTest::device(), &summary);
      },
      std::invalid_argument);
}

TEST_F(Reconstruct, AStopCallbackStopsAtTheCheckpoint) {
  TempDir dir;
  ReconstructOptions options = ShortRun(dir);
  int frames = 0;
  options.should_stop = [&] { return ++frames >= 3; };
  ReconstructSummary summary;
  recon::Reconstruct(options, device(), &summary);
  EXPECT_FALSE(summary.completed());
  EXPECT_EQ(summary.termination, opt::Termination::Stopped);
  EXPECT_NE(summary.BriefReport().find("resume"), std::string::npos) << summary.BriefReport();
  // Nothing was judged: a library caller that asks must not read "ok".
  EXPECT_FALSE(summary.diagnosis.ok());
  EXPECT_STREQ(ToString(summary.diagnosis.verdict), "none");
  EXPECT_NE(summary.FullReport().find("diagnosis: none"), std::string::npos) << summary.FullReport();
  EXPECT_TRUE(fs::exists(dir / "out/checkpoint.json"));
  EXPECT_FALSE(fs::exists(dir / "out/map.json"));
  EXPECT_TRUE(summary.written.empty());
}

TEST_F(Reconstruct, TheSummaryIsMapJsonAndTheWriterWritesItAgain) {
  TempDir dir;
  const ReconstructOptions options = ShortRun(dir);
  ReconstructSummary summary;
  recon::Reconstruct(options, device(), &summary);
  ASSERT_TRUE(summary.completed());
  const std::string map_json = Read(dir / "out/map.json");
  EXPECT_EQ(summary.ToJson().dump(2) + "\n", map_json);
  EXPECT_EQ(summary.map().size(), options.scene->parameters.size());
  EXPECT_EQ(summary.BriefReport().find('\n'), std::string::npos);
  EXPECT_NE(summary.FullReport().find("diagnosis: "), std::string::npos);
  EXPECT_NE(std::find(summary.written.begin(), summary.written.end(), dir / "out/map.json"), summary.written.end());

  const std::string chain_csv = Read(dir / "out/chain.csv");
  fs::remove(dir / "out/map.json");
  fs::remove(dir / "out/chain.csv");
  recon::WriteRunFiles(summary, *options.scene);
  EXPECT_EQ(Read(dir / "out/map.json"), map_json);
  EXPECT_EQ(Read(dir / "out/chain.csv"), chain_csv);
}

}  // namespace
}  // namespace vkr::test
