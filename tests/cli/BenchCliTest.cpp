// `vkrecon bench` as a script meets it: --json parses and carries the contract fields
// (docs/reference/CLI.md) for one small row, and a bad --only exits 2 with one line. No timing is
// asserted: these are benchmark figures, not timed tests.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;
using test::RunCommand;

const std::string kVkrecon = VKRECON_BINARY;
const fs::path kAssets = fs::path(VKRECON_SOURCE_DIR) / "assets";

std::string Quote(const fs::path& p) { return "'" + p.string() + "'"; }

TEST(BenchCli, JsonCarriesTheContractFields) {
  const auto r = RunCommand(kVkrecon + " bench --json --quick -q --only cameras/2 --assets " + Quote(kAssets));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);  // throws (fails the test) if not JSON
  EXPECT_TRUE(j.at("device").is_string());
  EXPECT_FALSE(j.at("device").get<std::string>().empty());
  ASSERT_EQ(j.at("rows").size(), 1u) << r.out;
  const nlohmann::json& row = j.at("rows").at(0);
  EXPECT_EQ(row.at("name"), "cameras/2");
  EXPECT_EQ(row.at("cameras"), 2);
  EXPECT_GE(row.at("batch").get<int>(), 1);
  EXPECT_GT(row.at("hypotheses_per_s").get<double>(), 0.0);
  for (const char* pass : {"depth", "view_texture", "composite"})
    EXPECT_TRUE(row.at("passes_ms").contains(pass)) << pass << " missing in " << row.dump();
  EXPECT_TRUE(row.at("share_of_ceiling").is_object());
  EXPECT_GT(row.at("device_bytes").get<double>(), 0.0);
  EXPECT_GT(j.at("ceilings").at("copy_bytes_per_s").get<double>(), 0.0);
  EXPECT_GT(j.at("ceilings").at("fill_fragments_per_s").get<double>(), 0.0);
  EXPECT_GT(j.at("memory").at("peak_rss_bytes").get<double>(), 0.0);
}

TEST(BenchCli, UnknownRowIsBadInput) {
  const auto r = RunCommand(kVkrecon + " bench --quick --only no_such_row --assets " + Quote(kAssets));
  EXPECT_EQ(r.exit_status, 2) << r.err;
  std::string err = r.err;
  while (!err.empty() && err.back() == '\n') err.pop_back();
  EXPECT_EQ(err.find('\n'), std::string::npos) << "more than one line:\n" << r.err;
  EXPECT_NE(r.err.find("--only"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no_such_row"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace vkr
