// `vkrecon run` as a user meets it: a run killed after a checkpoint resumes to exactly the
// result of an uninterrupted run; a scene the cameras cannot see is refused up front;
// images that show nothing of it end with a diagnosis; bad sampler options are bad input.

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

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

// A small, quick configuration of the box asset on images made in `dir`.
std::string SmallRun(const test::TempDir& dir, int iterations = 80) {
  return kVkrecon + " run -q " + Q(kBox / "scene.json") + " --set cameras=" + Q(dir / "images/cameras.json") +
         " --set images=" + Q(dir / "images") +
         " --set likelihood.atlas=64 --set likelihood.levels=2 --set sampler.iterations=" + std::to_string(iterations) +
         " --set sampler.chains=2 --set sampler.batch=4 --checkpoint-seconds 0.05";
}

// Starts `command` in the background (output discarded); its process id, or 0.
int StartInBackground(const std::string& command) {
  FILE* pipe = popen((command + " >/dev/null 2>&1 & echo $!").c_str(), "r");
  if (!pipe) return 0;
  int pid = 0;
  if (fscanf(pipe, "%d", &pid) != 1) pid = 0;
  pclose(pipe);
  return pid;
}

// SIGKILL, then wait until the process is gone (it is init's child: no waitpid).
void KillHard(int pid) {
  kill(pid, SIGKILL);
  for (int i = 0; i < 200 && kill(pid, 0) == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
}


nlohmann::json ReadJson(const fs::path& file) { return nlohmann::json::parse(test::ReadText(file)); }

TEST(RunCli, KilledRunResumesToTheSameResult) {
  test::TempDir dir;
  ASSERT_TRUE(SynthBoxImages(dir.path(), " --noise 8"));
  // With the local search before sampling (off by default), which a resume must not redo.
  const std::string run = SmallRun(dir) + " --set sampler.start_search=20";
  const auto straight = RunCommand(run + " -o " + Q(dir / "straight"));
  ASSERT_EQ(straight.exit_status, 0) << straight.err;

  // Start the same run, kill it hard once it has saved a checkpoint, then resume.
  const fs::path out = dir / "killed";
  const int pid = StartInBackground(run + " -o " + Q(out));
  ASSERT_GT(pid, 0);
  bool saw_checkpoint = false;
  for (int i = 0; i < 600 && !saw_checkpoint; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    saw_checkpoint = fs::exists(out / "checkpoint.json");
  }
  ASSERT_TRUE(saw_checkpoint);
  KillHard(pid);
  ASSERT_FALSE(fs::exists(out / "map.json")) << "the run finished before it was killed; nothing was tested";

  const auto resumed = RunCommand(run + " -o " + Q(out) + " --resume");
  ASSERT_EQ(resumed.exit_status, 0) << resumed.err;
  const nlohmann::json a = ReadJson(dir / "straight/map.json"), b = ReadJson(out / "map.json");
  EXPECT_EQ(a["parameters"], b["parameters"]);  // bit-identical numbers
  // The asset estimates σ at the mode (`sigma: auto`), and the resumed run kept it.
  EXPECT_EQ(a["calibration"], b["calibration"]);
  EXPECT_TRUE(a["calibration"]["sigma_estimated"].get<bool>());
  EXPECT_GT(a["calibration"]["kappa"].get<double>(), 0.0);
  EXPECT_EQ(a["settings"]["likelihood"]["sigma"], "auto");
  EXPECT_EQ(a["settings"]["likelihood"]["edges"], true) << "on by default";
  EXPECT_TRUE(a["settings"]["max_side"].is_null()) << "the photographs at their size";
  EXPECT_EQ(test::ReadText(dir / "straight/chain.csv"), test::ReadText(out / "chain.csv"));
  for (const char* f : {"composite.exr", "composite.png", "model.glb", "chain.csv"}) EXPECT_TRUE(fs::exists(out / f)) << f;
  // One CmdStan CSV per posterior chain (its format is tested in optimiser/Sampler.StanCsv…),
  // equal too: 2 chains of 2 replicas, each replica a chain of its own once settled.
  const int chains = a["posterior_chains"].get<int>();
  EXPECT_EQ(chains, 4);
  for (int k = 1; k <= chains; ++k) {
    const std::string f = "chains/stan-" + std::to_string(k) + ".csv";
    EXPECT_EQ(test::ReadText(dir / "straight" / f), test::ReadText(out / f)) << f;
  }
  EXPECT_FALSE(fs::exists(out / ("chains/stan-" + std::to_string(chains + 1) + ".csv")));
  EXPECT_EQ(a["sampling"]["ended_by"], "iterations");  // a fixed count: no time limit by default
  // The local search before sampling ran once, before the first checkpoint; the resumed run
  // compared the same mode at the end and counted its evaluations alike.
  EXPECT_GT(a["start_search"]["evaluations"].get<int>(), 0);
  EXPECT_EQ(a["start_search"], b["start_search"]);
  EXPECT_EQ(a["evaluations"], b["evaluations"]);
  EXPECT_TRUE(a["start_search"]["log_posterior_at_end"].is_number()) << a["start_search"].dump();
}

// Convergence-driven length with a time limit that is up at once: sampling ends as soon as
// the schedule's iterations are done, map.json and the diagnosis say so, and the verdict is
// not ok.
TEST(RunCli, ATimeLimitEndsTheSamplingAndTheDiagnosisSaysSo) {
  test::TempDir dir;
  ASSERT_TRUE(SynthBoxImages(dir.path(), ""));
  const fs::path out = dir / "out";
  const auto r = RunCommand(SmallRun(dir, 40) + " --set sampler.until_converged=true --time-limit 0.001 -o " + Q(out));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const nlohmann::json map = nlohmann::json::parse(test::ReadText(out / "map.json"));
  EXPECT_EQ(map["sampling"]["ended_by"], "time_limit");
  EXPECT_EQ(map["iterations"].get<int>(), 40);  // the schedule first, then the limit
  EXPECT_EQ(map["settings"]["time_limit"], 0.001);
  EXPECT_NE(map["diagnosis"]["verdict"], "ok");  // unsettled at least (40 iterations also leave a model_error)
  EXPECT_NE(map["diagnosis"].dump().find("ended at the time limit"), std::string::npos) << map["diagnosis"].dump();
  EXPECT_NE(r.err.find("--time-limit"), std::string::npos) << r.err;
}

// The scene's sandwich block size reaches the calibration at the mode (map.json says which
// blocks κ was measured over) and the recorded settings.
TEST(RunCli, TheSandwichBlocksOfTheSceneAreTheCalibrations) {
  test::TempDir dir;
  ASSERT_TRUE(SynthBoxImages(dir.path(), " --noise 8"));
  const fs::path out = dir / "out";
  const auto r = RunCommand(SmallRun(dir, 40) + " --set likelihood.sandwich_blocks=16 -o " + Q(out));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const nlohmann::json map = ReadJson(out / "map.json");
  EXPECT_EQ(map["calibration"]["block"], 16) << map["calibration"].dump();
  EXPECT_EQ(map["settings"]["likelihood"]["sandwich_blocks"], 16);
  const auto bad = RunCommand(SmallRun(dir, 40) + " --set likelihood.sandwich_blocks=24 -o " + Q(dir / "bad"));
  EXPECT_EQ(bad.exit_status, 2);
  EXPECT_NE(bad.err.find("likelihood.sandwich_blocks"), std::string::npos) << bad.err;
}

// Kill anywhere (docs/internals/HARDENING.md, "Kill anywhere"): SIGKILL at 20 moments drawn
// uniformly over an uninterrupted run's duration (loading, sampling, settling, writing the
// outputs), each resumed with --resume, must end with the uninterrupted run's map and chain every
// time. A shorter run than above keeps the 20 cycles to a couple of minutes.
TEST(RunCli, KilledAnywhereAndResumedGivesTheUninterruptedResult) {
  test::TempDir dir;
  ASSERT_TRUE(SynthBoxImages(dir.path(), " --noise 8"));
  const std::string run = SmallRun(dir, 40);
  const auto started = std::chrono::steady_clock::now();
  const auto uninterrupted = RunCommand(run + " -o " + Q(dir / "straight"));
  // Its stderr, should it fail: CI once saw this run abort (exit 134) and nothing said where.
  ASSERT_EQ(uninterrupted.exit_status, 0) << uninterrupted.err;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const nlohmann::json straight = ReadJson(dir / "straight/map.json");
  const std::string straight_chain = test::ReadText(dir / "straight/chain.csv");

  std::mt19937 rng(13);
  double span = seconds;
  int interrupted = 0;
  // Up to 40 tries for 20 interruptions: on a loaded machine the straight run may have been
  // slower than the killed copies, whose kills then land after their end (CI saw 12 of 20).
  // Such a kill still checks the resume of a finished run, and narrows the span to it.
  for (int k = 0; k < 40 && interrupted < 20; ++k) {
    const fs::path out = dir / ("killed" + std::to_string(k));
    const double at = std::uniform_real_distribution<double>(0.0, span)(rng);
    const int pid = StartInBackground(run + " -o " + Q(out));
    ASSERT_GT(pid, 0);
    std::this_thread::sleep_for(std::chrono::duration<double>(at));
    KillHard(pid);
    if (!fs::exists(out / "map.json")) ++interrupted;
    else span = std::max(at, 0.5 * seconds);
    const auto resumed = RunCommand(run + " -o " + Q(out) + " --resume");
    ASSERT_EQ(resumed.exit_status, 0) << "killed at " << at << " s: " << resumed.err;
    const nlohmann::json map = ReadJson(out / "map.json");
    EXPECT_EQ(map["parameters"], straight["parameters"]) << "killed at " << at << " s";
    EXPECT_EQ(map["calibration"], straight["calibration"]) << "killed at " << at << " s";
    EXPECT_EQ(test::ReadText(out / "chain.csv"), straight_chain) << "killed at " << at << " s";
  }
  // Kills must land inside the run, or the test proved little.
  EXPECT_GE(interrupted, 15) << "only " << interrupted << " kills interrupted the run";
}

TEST(RunCli, ATruncatedOrCorruptCheckpointOrOtherSettingsAreBadInputNotACrashOrARestart) {
  test::TempDir dir;
  ASSERT_TRUE(SynthBoxImages(dir.path(), ""));
  const fs::path out = dir / "out";
  ASSERT_EQ(RunCommand(SmallRun(dir, 20) + " -o " + Q(out)).exit_status, 0);
  const std::string checkpoint = test::ReadText(out / "checkpoint.json");
  // Resumed under another likelihood, the chains would sample two posteriors as one.
  const auto other = RunCommand(SmallRun(dir, 20) + " --set likelihood.edges=false -o " + Q(out) + " --resume");
  EXPECT_EQ(other.exit_status, 2) << other.err;
  EXPECT_NE(other.err.find("checkpoint.json: likelihood.edges: the checkpoint's run had true, this one has false"),
            std::string::npos) << other.err;
  EXPECT_EQ(std::count(other.err.begin(), other.err.end(), '\n'), 1) << other.err;
  EXPECT_EQ(test::ReadText(out / "checkpoint.json"), checkpoint) << "a refused resume leaves the checkpoint alone";
  // So would other photographs: max_side shrinks them.
  const auto smaller = RunCommand(SmallRun(dir, 20) + " --set max_side=80 -o " + Q(out) + " --resume");
  EXPECT_EQ(smaller.exit_status, 2) << smaller.err;
  EXPECT_NE(smaller.err.find("checkpoint.json: max_side: the checkpoint's run had 0, this one has 80"), std::string::npos)
      << smaller.err;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"truncated", checkpoint.substr(0, checkpoint.size() / 2)},
      {"empty", ""},
      {"not JSON", "\x89PNG garbage"},
      {"another format", R"({"format": "something-else", "version": 2})"},
  };
  for (const auto& [what, text] : cases) {
    test::WriteText(out / "checkpoint.json", text);
    const auto r = RunCommand(SmallRun(dir, 20) + " -o " + Q(out) + " --resume");
    EXPECT_EQ(r.exit_status, 2) << what << ": " << r.err;
    EXPECT_NE(r.err.find("checkpoint.json"), std::string::npos) << what << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << what << ", one line: " << r.err;
  }
}

TEST(RunCli, CamerasThatSeeNothingAreRefusedWithAReason) {
  test::TempDir dir;
  ASSERT_TRUE(SynthBoxImages(dir.path(), ""));
  // Move the whole scene 100 m away from every camera.
  const auto r = RunCommand(SmallRun(dir) + " --set 'nodes[0].transforms=[{\"translate\": [100, 0, 0]}, {\"scale\": [5, 5, 1]}]'"
                            " --set 'nodes[1].transforms=[{\"translate\": [\"x+100\", \"y\", 0]}, {\"rotate\": [0, 0, \"yaw\"]}, {\"scale\": [\"w\", \"d\", \"h\"]}]'"
                            " -o " + Q(dir / "out"));
  EXPECT_EQ(r.exit_status, 2) << r.err;
  EXPECT_NE(r.err.find("see nothing"), std::string::npos) << r.err;
}

TEST(RunCli, ImagesThatShowNothingOfTheSceneEndWithADiagnosis) {
  // Noise of sd 120 drowns the box: whatever the sampler finds, the views disagree far
  // beyond camera noise, and the run must say so (exit 1) rather than report an answer.
  test::TempDir dir;
  ASSERT_TRUE(SynthBoxImages(dir.path(), " --noise 120"));
  const auto r = RunCommand(SmallRun(dir) + " -o " + Q(dir / "out"));
  EXPECT_EQ(r.exit_status, 1) << r.err;
  EXPECT_NE(r.err.find("far beyond camera noise"), std::string::npos) << r.err;
  const nlohmann::json map = ReadJson(dir / "out/map.json");
  EXPECT_FALSE(map["diagnosis"]["ok"].get<bool>());
  EXPECT_GT(map["diagnosis"]["reprojection_rms"].get<double>(), 48.0);
}

TEST(RunCli, BadSamplerOptionsAreBadInputNamingTheField) {
  test::TempDir dir;
  ASSERT_TRUE(SynthBoxImages(dir.path(), ""));
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"sampler.bogus=1", "sampler.bogus: unknown option"},
      {"sampler.settle=3", "sampler.settle: expected true or false"},
      {"sampler.settle_rounds=0", "settle_rounds must be"},
  };
  for (const auto& [set, message] : cases) {
    const auto r = RunCommand(SmallRun(dir) + " --set " + set + " -o " + Q(dir / "out"));
    EXPECT_EQ(r.exit_status, 2) << set << ": " << r.err;
    EXPECT_NE(r.err.find("scene.json: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
  }
}

// Nothing to resume (a run killed before its first checkpoint, or a mistyped folder): the
// run starts from the beginning, says so, and ends as a run started without --resume.
TEST(RunCli, ResumeWithNothingToResumeStartsTheRunAndSaysSo) {
  test::TempDir dir;
  ASSERT_TRUE(SynthBoxImages(dir.path(), ""));
  const auto straight = RunCommand(SmallRun(dir, 20) + " -o " + Q(dir / "straight"));
  ASSERT_EQ(straight.exit_status, 0) << straight.err;
  const auto r = RunCommand(SmallRun(dir, 20) + " --resume -o " + Q(dir / "none"));
  EXPECT_EQ(r.exit_status, 0) << r.err;
  EXPECT_NE(r.err.find("checkpoint.json does not exist"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("starting the run from the beginning"), std::string::npos) << r.err;
  EXPECT_EQ(ReadJson(dir / "none/map.json")["parameters"], ReadJson(dir / "straight/map.json")["parameters"]);
}

}  // namespace
}  // namespace vkr
