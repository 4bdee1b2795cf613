// `vkrecon bench --only peers --quick` (apps/PeersBench.h): one seed of box and poster, every
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
  EXPECT_EQ(nlohmann::json::parse(test::ReadText(dir / "peers.json")).at("rows"), j.at("rows"));
}

TEST(PeersBenchCli, UnknownAssetFolderIsBadInput) {
  test::TempDir dir;
  const auto r = RunCommand(kVkrecon + " bench --only peers --quick --assets " + Quote(dir.path()));
  test::ExpectBadInput(r, {"scene.json", "unknown asset"});
}

}  // namespace
}  // namespace vkr
