// `vkrecon init` end to end: the summary it prints, the files it writes, and bad input as exit
// status 2 with one line (recon/SceneInit.h does the work; tests/recon checks its numbers).

#include <gtest/gtest.h>

#include "tests/cli/CliTestUtil.h"
#include "tests/recon/SyntheticColmap.h"

namespace vkr::test {
namespace {

std::string Init(const std::string& args) { return std::string(VKRECON_BINARY) + " init " + args; }

TEST(InitCli, WritesTheSceneFolderAndSaysWhatItFound) {
  TempDir dir;
  const SyntheticColmap s = MakeSyntheticColmap("house", dir.path(), true, 11);
  const std::string scale = std::to_string(s.far_a) + "," + std::to_string(s.far_b) + "=" + std::to_string(s.far_metres);
  const CommandResult r = RunCommand(Init(Quote(s.sparse) + " -o " + Quote(dir / "scene") +
                                          " --template house --scale-points " + scale + " --max-side 320"));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  std::cout << r.out;
  EXPECT_NE(r.out.find("model: 7 images, 3000 points"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("units: metres"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("next: check the starter scene over the photographs with `vkrecon preview"), std::string::npos);
  for (const char* file : {"cameras.json", "points.ply", "scene.json", "init.json"})
    EXPECT_TRUE(std::filesystem::exists(dir / "scene" / file)) << file;
  EXPECT_NE(ReadText(dir / "scene/scene.json").find("\"rh\""), std::string::npos);
  // The 640 × 480 photographs are larger than --max-side: the scene says to shrink them.
  EXPECT_NE(r.out.find("shrunk to at most 320"), std::string::npos) << r.out;
  EXPECT_NE(ReadText(dir / "scene/scene.json").find("\"max_side\": 320"), std::string::npos);
}

TEST(InitCli, BadInputIsOneLineAndExitTwo) {
  TempDir dir;
  const SyntheticColmap s = MakeSyntheticColmap("box", dir.path(), false, 12);
  std::filesystem::remove(s.images / "cam2.pgm");
  const std::string base = Quote(s.sparse) + " -o " + Quote(dir / "scene");
  const std::pair<std::string, std::string> cases[] = {
      {base, "cam2.pgm: photograph missing"},
      {base + " --template tower", "--template: unknown template 'tower'"},
      {base + " --up 0,1", "--up: expected X,Y,Z"},
      {base + " --max-side 8", "--max-side: expected 0 (none) or 16 to 65536"},
      {Quote(dir / "nothing") + " -o " + Quote(dir / "scene"), "nothing: not a folder"},
  };
  for (const auto& [args, message] : cases) ExpectBadInput(RunCommand(Init(args)), {message});
  EXPECT_FALSE(std::filesystem::exists(dir / "scene"));
}

}  // namespace
}  // namespace vkr::test
