// `vkrecon bench --only peers --quick` (bench/peers/PeersBench.h): one seed of box and poster, every
// method; the JSON has a row per asset and method whose numbers hang together — budgets kept,
// "reached" only with what it took, errors of a search that found the box, not of the prior.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "tests/cli/CliTestUtil.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;
using test::Quote;
using test::RunCommand;

const std::string kVkrecon = VKRECON_BINARY;
const fs::path kAssets = fs::path(VKRECON_SOURCE_DIR) / "assets";

TEST(PeersBenchCli, QuickRunHasARowPerAssetAndMethodThatMakesSense) {
  test::TempDir dir;
  const auto r = RunCommand(kVkrecon + " bench --only peers --quick --json --assets " + Quote(kAssets) + " --work " +
                            Quote(dir.path()));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("assets"), nlohmann::json({"box", "poster"}));
  EXPECT_EQ(j.at("seeds"), nlohmann::json({1}));
  EXPECT_EQ(j.at("sigma"), 16.0);
  const double budget = j.at("budget").get<double>();
  const std::set<std::string> methods = {"run", "bobyqa", "neldermead", "sbplx", "crs2lm", "isres"};
  ASSERT_EQ(j.at("rows").size(), 2 * methods.size()) << j.dump(1);
  std::set<std::string> seen;
  for (const nlohmann::json& row : j.at("rows")) {
    const std::string method = row.at("method"), who = row.at("asset").get<std::string>() + "/" + method;
    seen.insert(who);
    EXPECT_TRUE(methods.count(method)) << who;
    const double evaluations = row.at("evaluations"), equivalents = row.at("equivalents");
    EXPECT_GT(evaluations, 10) << who;
    // Coarse evaluations count less than one: never more equivalents than evaluations.
    EXPECT_LE(equivalents, evaluations + 1e-9) << who;
    EXPECT_GT(row.at("seconds").get<double>(), 0.0) << who;
    if (method != "run") EXPECT_LE(equivalents, budget + 1e-6) << who;
    else EXPECT_GT(evaluations, 60 * 16) << "60 iterations of 16 hypotheses at least";
    // "Reached" carries what it took, no more than was spent in all.
    if (row.at("reached").get<bool>()) {
      EXPECT_LE(row.at("equivalents_to").get<double>(), equivalents + 1e-9) << who;
      EXPECT_LE(row.at("evaluations_to").get<double>(), evaluations) << who;
      EXPECT_LE(row.at("seconds_to").get<double>(), row.at("seconds").get<double>() + 1e-9) << who;
    } else {
      EXPECT_TRUE(row.at("equivalents_to").is_null()) << who;
    }
    const double median = row.at("median_error"), largest = row.at("max_error");
    EXPECT_GE(largest, median) << who;
    EXPECT_GE(median, 0.0) << who;
    // The local searches and run find the box; the prior centre is 5-30 % away on these assets.
    if (method == "run" || method == "bobyqa") EXPECT_LT(median, 0.03) << who;
  }
  EXPECT_EQ(seen.size(), 2 * methods.size()) << "a row per asset and method";
  // The rows are also kept in the work folder as they come.
  const nlohmann::json kept = nlohmann::json::parse(test::ReadText(dir / "peers.json"));
  ASSERT_EQ(kept.at("rows"), j.at("rows"));

  // Cut short after box (poster's rows gone), then resumed: box's rows are kept as they were
  // (a planted time proves they were not measured again) and poster's are measured.
  nlohmann::json cut = kept;
  cut["rows"] = nlohmann::json::array();
  for (nlohmann::json row : kept.at("rows")) {
    if (row.at("asset") != "box") continue;
    if (row.at("method") == "run") row["seconds"] = 12345.0;
    cut["rows"].push_back(row);
  }
  test::WriteText(dir / "peers.json", cut.dump(2));
  const std::string resume = kVkrecon + " bench --only peers --quick --json --resume --assets " + Quote(kAssets) +
                             " --work " + Quote(dir.path());
  const auto resumed = RunCommand(resume);
  ASSERT_EQ(resumed.exit_status, 0) << resumed.err;
  EXPECT_NE(resumed.err.find("box seed 1:"), std::string::npos) << resumed.err;
  EXPECT_NE(resumed.err.find("(kept)"), std::string::npos) << resumed.err;
  const nlohmann::json again = nlohmann::json::parse(resumed.out);
  ASSERT_EQ(again.at("rows").size(), 2 * methods.size()) << again.dump(1);
  for (const nlohmann::json& row : again.at("rows")) {
    const std::string who = row.at("asset").get<std::string>() + "/" + row.at("method").get<std::string>();
    if (who == "box/run") EXPECT_EQ(row.at("seconds"), 12345.0) << "box was measured again";
    if (row.at("asset") == "poster") EXPECT_GT(row.at("evaluations").get<double>(), 10) << who;
  }

  // Resuming rows of another device or other settings would mix what does not compare.
  nlohmann::json other = again;
  other["device"] = "another GPU";
  test::WriteText(dir / "peers.json", other.dump(2));
  test::ExpectBadInput(RunCommand(resume), {"peers.json", "device", "another GPU"});
  other = again;
  other["sigma"] = 8.0;
  test::WriteText(dir / "peers.json", other.dump(2));
  test::ExpectBadInput(RunCommand(resume), {"peers.json", "sigma", "other settings"});
  other = again;
  other["wall_s"] = "soon";
  test::WriteText(dir / "peers.json", other.dump(2));
  test::ExpectBadInput(RunCommand(resume), {"peers.json", "wall_s", "cannot resume"});
}

TEST(PeersBenchCli, UnknownAssetFolderIsBadInput) {
  test::TempDir dir;
  const auto r = RunCommand(kVkrecon + " bench --only peers --quick --assets " + Quote(dir.path()));
  test::ExpectBadInput(r, {"scene.json", "unknown asset"});
}

TEST(PeersBenchCli, ResumeNeedsTheWorkFolderAndPeers) {
  test::ExpectBadInput(RunCommand(kVkrecon + " bench --only peers --quick --resume --assets " + Quote(kAssets)),
                       {"--resume", "--work"});
  test::ExpectBadInput(RunCommand(kVkrecon + " bench --only house --resume"), {"--resume", "peers"});
  test::TempDir dir;
  test::WriteText(dir / "peers.json", "{\"rows\": [");
  test::ExpectBadInput(RunCommand(kVkrecon + " bench --only peers --quick --resume --assets " + Quote(kAssets) +
                                  " --work " + Quote(dir.path())),
                       {"peers.json", "not JSON"});
}

}  // namespace
}  // namespace vkr
