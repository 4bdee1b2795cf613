// `mpirun -n R vkrecon run` (docs/guide/SCALE_OUT.md): with the same seed and replica layout, 1, 2
// and 4 ranks (oversubscribed on this machine, loopback) give a map.json and chain.csv
// bit-identical to a plain one-process run; a rank killed mid-run ends the job without a
// result, and `--resume` under mpirun finishes with the uninterrupted result. Skipped when
// vkrecon was built without MPI or mpirun is missing.

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "recon/DistributedTarget.h"
#include "tests/cli/CliTestUtil.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;
using test::RunCommand;
using test::SynthBoxImages;

const std::string kVkrecon = VKRECON_BINARY;
const fs::path kBox = fs::path(VKRECON_SOURCE_DIR) / "assets/box";

std::string Q(const fs::path& p) { return "'" + p.string() + "'"; }

#ifdef VKRECON_MPIEXEC
// mpirun for R ranks on this one machine: more ranks than cores, as root if need be, the
// shared-memory transport without the single-copy mechanism containers often forbid.
std::string Mpirun(int ranks) {
  return std::string(VKRECON_MPIEXEC) + " --oversubscribe" + (getuid() == 0 ? " --allow-run-as-root" : "") +
         " --mca btl self,vader --mca btl_vader_single_copy_mechanism none -n " + std::to_string(ranks) + " ";
}
#endif

// A small box run: quarter size, 4 chains of 2 temperatures (batch 8).
std::string BoxRun(const fs::path& dir, int iterations = 40) {
  return kVkrecon + " run -q " + Q(kBox / "scene.json") + " --set cameras=" + Q(dir / "images/cameras.json") +
         " --set images=" + Q(dir / "images") +
         " --set likelihood.atlas=64 --set likelihood.levels=2 --set sampler.iterations=" + std::to_string(iterations) +
         " --set sampler.chains=4 --set sampler.batch=8 --checkpoint-seconds 0.05";
}


TEST(ScaleOut, SlicesAreContiguousAndBalanced) {
  const recon::Slices s = recon::SliceBatch(10, 4);
  EXPECT_EQ(s.counts, (std::vector<int>{3, 3, 2, 2}));
  EXPECT_EQ(s.offsets, (std::vector<int>{0, 3, 6, 8}));
  const recon::Slices few = recon::SliceBatch(2, 4);  // fewer hypotheses than ranks: some idle
  EXPECT_EQ(few.counts, (std::vector<int>{1, 1, 0, 0}));
  EXPECT_EQ(few.offsets, (std::vector<int>{0, 1, 2, 2}));
}

#ifdef VKRECON_MPIEXEC

TEST(ScaleOut, RanksGiveTheOneProcessResultBitForBit) {
  test::TempDir dir;
  ASSERT_TRUE(SynthBoxImages(dir.path(), " --noise 8"));
  const auto plain = RunCommand(BoxRun(dir.path()) + " -o " + Q(dir / "plain"));
  ASSERT_EQ(plain.exit_status, 0) << plain.err;
  const std::string map = test::ReadText(dir / "plain/map.json"), chain = test::ReadText(dir / "plain/chain.csv");
  for (int ranks : {1, 2, 4}) {
    const fs::path out = dir / ("n" + std::to_string(ranks));
    const auto r = RunCommand(Mpirun(ranks) + BoxRun(dir.path()) + " -o " + Q(out));
    ASSERT_EQ(r.exit_status, 0) << ranks << " ranks:\n" << r.err;
    // The whole file: parameters, calibration, diagnosis and settings (one device model).
    EXPECT_EQ(map, test::ReadText(out / "map.json")) << ranks << " ranks";
    EXPECT_EQ(chain, test::ReadText(out / "chain.csv")) << ranks << " ranks";
    EXPECT_EQ(fs::exists(out / "scale_out.json"), ranks > 1) << ranks << " ranks";
  }
  const auto cost = nlohmann::json::parse(test::ReadText(dir / "n4/scale_out.json"));
  EXPECT_EQ(cost["ranks"], 4);
  EXPECT_GT(cost["calls"].get<int>(), 40);
}

// The pid of the process that is rank `rank` of the job started by mpirun `parent`, or 0.
int RankPid(int parent, int rank) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream stat(entry.path() / "stat");
    std::string pid, comm, state;
    int ppid = 0;
    if (!(stat >> pid >> comm >> state >> ppid) || ppid != parent) continue;
    std::ifstream environ(entry.path() / "environ", std::ios::binary);
    const std::string env((std::istreambuf_iterator<char>(environ)), std::istreambuf_iterator<char>());
    if (env.find(std::string("OMPI_COMM_WORLD_RANK=") + std::to_string(rank) + '\0') != std::string::npos)
      return std::stoi(name);
  }
  return 0;
}

TEST(ScaleOut, KilledRankEndsTheJobAndResumeFinishesTheSameRun) {
  test::TempDir dir;
  ASSERT_TRUE(SynthBoxImages(dir.path(), " --noise 8"));
  const auto plain = RunCommand(BoxRun(dir.path(), 60) + " -o " + Q(dir / "plain"));
  ASSERT_EQ(plain.exit_status, 0) << plain.err;

  const fs::path out = dir / "killed";
  const std::string log = (dir / "killed.log").string();
  FILE* pipe = popen(("exec " + Mpirun(2) + BoxRun(dir.path(), 60) + " -o " + Q(out) + " >" + Q(log) +
                      " 2>&1 & echo $!").c_str(), "r");
  ASSERT_TRUE(pipe);
  int mpirun = 0;
  ASSERT_EQ(fscanf(pipe, "%d", &mpirun), 1);
  pclose(pipe);
  // Once rank 0 has checkpointed a few times, kill rank 1 hard.
  int victim = 0;
  for (int i = 0; i < 1200 && !(victim && fs::exists(out / "checkpoint.json")); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (!victim) victim = RankPid(mpirun, 1);
  }
  ASSERT_GT(victim, 0);
  ASSERT_TRUE(fs::exists(out / "checkpoint.json"));
  std::this_thread::sleep_for(std::chrono::seconds(3));
  ASSERT_EQ(kill(victim, SIGKILL), 0);
  for (int i = 0; i < 1200 && kill(mpirun, 0) == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_NE(kill(mpirun, 0), 0) << "mpirun did not end the job";
  ASSERT_FALSE(fs::exists(out / "map.json")) << "the run finished before it was killed; nothing was tested";
  EXPECT_NE(test::ReadText(log).find("--resume"), std::string::npos) << test::ReadText(log);

  const auto resumed = RunCommand(Mpirun(2) + BoxRun(dir.path(), 60) + " -o " + Q(out) + " --resume");
  ASSERT_EQ(resumed.exit_status, 0) << resumed.err;
  EXPECT_EQ(test::ReadText(dir / "plain/map.json"), test::ReadText(out / "map.json"));
  EXPECT_EQ(test::ReadText(dir / "plain/chain.csv"), test::ReadText(out / "chain.csv"));
}

#else

TEST(ScaleOut, RanksGiveTheOneProcessResultBitForBit) {
  GTEST_SKIP() << "vkrecon was built without MPI (or mpirun was not found): nothing to test";
}

#endif

// `vkrecon run FOLDER -o OUT` (docs/guide/SCALE_OUT.md, "Many scenes"): two small box scenes with
// different seeds in FOLDER/a and FOLDER/b, each written with absolute paths.
fs::path WriteTwoScenes(const fs::path& dir) {
  nlohmann::json scene = nlohmann::json::parse(std::ifstream(kBox / "scene.json"));
  scene["images"] = (dir / "images").string();
  scene["cameras"] = (dir / "images/cameras.json").string();
  for (auto& node : scene["nodes"])
    if (node.contains("albedo")) node["albedo"] = (kBox / node["albedo"].get<std::string>()).string();
  scene["likelihood"] = {{"atlas", 64}, {"levels", 2}};
  int seed = 1;
  for (const char* name : {"a", "b"}) {
    scene["sampler"] = {{"iterations", 30}, {"chains", 2}, {"batch", 4}, {"seed", seed++}};
    fs::create_directories(dir / "scenes" / name);
    std::ofstream(dir / "scenes" / name / "scene.json") << scene.dump(2);
  }
  return dir / "scenes";
}

nlohmann::json ReadMap(const fs::path& file) { return nlohmann::json::parse(std::ifstream(file)); }

TEST(ManyScenes, AFolderOfScenesRunsEachIntoItsOwnFolderWithASummary) {
  test::TempDir dir;
  ASSERT_TRUE(SynthBoxImages(dir.path(), " --noise 8"));
  const fs::path scenes = WriteTwoScenes(dir.path());
  const auto listed = RunCommand(kVkrecon + " run -q " + Q(scenes) + " -o " + Q(dir / "out"));
  ASSERT_EQ(listed.exit_status, 0) << listed.err;
  EXPECT_NE(listed.err.find("2 scene(s) on 1 rank(s)"), std::string::npos) << listed.err;
  for (const char* name : {"a", "b"}) {
    SCOPED_TRACE(name);
    // Each is the run of that scene alone.
    const auto alone = RunCommand(kVkrecon + " run -q " + Q(scenes / name / "scene.json") + " -o " + Q(dir / "alone" / name));
    ASSERT_EQ(alone.exit_status, 0) << alone.err;
    EXPECT_EQ(ReadMap(dir / "out" / name / "map.json")["parameters"], ReadMap(dir / "alone" / name / "map.json")["parameters"]);
    EXPECT_EQ(test::ReadText(dir / "out" / name / "chain.csv"), test::ReadText(dir / "alone" / name / "chain.csv"));
  }
  EXPECT_NE(ReadMap(dir / "out/a/map.json")["parameters"], ReadMap(dir / "out/b/map.json")["parameters"]);  // two seeds
  const std::string summary = test::ReadText(dir / "out/summary.csv");
  EXPECT_EQ(std::count(summary.begin(), summary.end(), '\n'), 3) << summary;
  EXPECT_EQ(summary.rfind("scene,file,rank,exit_status,verdict,seconds,output\na,", 0), 0u) << summary;

  // A list file: a missing scene is bad input naming the list and its line, before any run.
  std::ofstream(dir / "list.txt") << "# two scenes\nscenes/a\n\nscenes/nowhere/scene.json\n";
  const auto bad = RunCommand(kVkrecon + " run -q " + Q(dir / "list.txt") + " -o " + Q(dir / "out2"));
  EXPECT_EQ(bad.exit_status, 2);
  EXPECT_NE(bad.err.find("list.txt: line 4: no scene file"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "out2"));
  std::ofstream(dir / "twice.txt") << "scenes/a\nscenes/a/scene.json\n";
  const auto twice = RunCommand(kVkrecon + " run -q " + Q(dir / "twice.txt") + " -o " + Q(dir / "out3"));
  EXPECT_EQ(twice.exit_status, 2);
  EXPECT_NE(twice.err.find("line 2: a second scene named 'a'"), std::string::npos) << twice.err;

#ifdef VKRECON_MPIEXEC
  // Over two ranks: scene a on rank 0, b on rank 1, each the same run as alone.
  const auto spread = RunCommand(Mpirun(2) + kVkrecon + " run -q " + Q(scenes) + " -o " + Q(dir / "mpi"));
  ASSERT_EQ(spread.exit_status, 0) << spread.err;
  EXPECT_NE(spread.err.find("2 scene(s) on 2 rank(s)"), std::string::npos) << spread.err;
  for (const char* name : {"a", "b"})
    EXPECT_EQ(test::ReadText(dir / "mpi" / name / "chain.csv"), test::ReadText(dir / "alone" / name / "chain.csv")) << name;
  EXPECT_NE(test::ReadText(dir / "mpi/summary.csv").find("\nb,"), std::string::npos);
  EXPECT_NE(test::ReadText(dir / "mpi/summary.csv").find(",1,0,"), std::string::npos);  // b: rank 1, exit 0
#endif
}

}  // namespace
}  // namespace vkr
