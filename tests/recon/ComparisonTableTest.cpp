// The table of `vkrecon compare` (recon/SceneComparison.h): Bayes factors and model
// probabilities with their errors against closed forms and finite differences, the verdicts
// and doubts, reading a run's map.json, and refusing rows of different likelihoods.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "engine/common/InputError.h"
#include "recon/SceneComparison.h"
#include "tests/common/TestFiles.h"

namespace vkr::test {
namespace {

namespace fs = std::filesystem;
using recon::ComparedScene;

// A row as a trustworthy run would give it.
ComparedScene Row(const std::string& name, double log_z, double se) {
  ComparedScene r;
  r.name = name;
  r.log_z = r.log_z_ti = log_z;
  r.se = r.se_ti = se;
  r.agree = true;
  r.ess = 500;
  r.min_swap = 0.5;
  r.likelihood = {{"sigma", 8.0}, {"position_sd", 0.5}, {"kappa", 3.0}, {"kind", "surface"},
                  {"photometric", "affine"}, {"clutter", false}};
  return r;
}

TEST(ComparisonTable, TwoScenesMatchTheClosedForm) {
  std::vector<ComparedScene> rows = {Row("box", -110.0, 0.4), Row("house", -100.0, 0.3)};
  recon::TabulateComparison(&rows);
  const double p_box = 1.0 / (1.0 + std::exp(10.0));
  EXPECT_NEAR(rows[0].probability, p_box, 1e-15);
  EXPECT_NEAR(rows[1].probability, 1.0 - p_box, 1e-15);
  EXPECT_DOUBLE_EQ(rows[0].log_bayes_factor, -10.0);
  EXPECT_DOUBLE_EQ(rows[0].se_log_bayes_factor, 0.5);  // 0.3 and 0.4 in quadrature
  EXPECT_EQ(rows[1].log_bayes_factor, 0.0);
  EXPECT_EQ(rows[1].se_log_bayes_factor, 0.0);
  // p_box = logistic(log Z_box − log Z_house): its slope p(1 − p) times the difference's error.
  const double se = p_box * (1.0 - p_box) * 0.5;
  EXPECT_NEAR(rows[0].se_probability, se, 1e-12 * se + 1e-300);
  EXPECT_NEAR(rows[1].se_probability, se, 1e-12 * se + 1e-300);
  EXPECT_EQ(rows[1].verdict, "best, decisive");
  EXPECT_EQ(rows[0].verdict, "rejected");
  EXPECT_TRUE(rows[0].doubts.empty());
}

TEST(ComparisonTable, ProbabilityErrorsMatchFiniteDifferences) {
  std::vector<ComparedScene> rows = {Row("a", -1e6, 0.7), Row("b", -1e6 + 1.3, 0.2), Row("c", -1e6 + 0.4, 1.1)};
  recon::TabulateComparison(&rows);
  double total = 0.0;
  for (const ComparedScene& r : rows) total += r.probability;
  EXPECT_NEAR(total, 1.0, 1e-12);  // and no overflow at log Z = −10⁶
  // Var p_i = Σ_j (∂p_i/∂log Z_j)² se_j², the slopes by central differences.
  for (size_t i = 0; i < rows.size(); ++i) {
    double variance = 0.0;
    for (size_t j = 0; j < rows.size(); ++j) {
      std::vector<ComparedScene> up = rows, down = rows;
      up[j].log_z += 1e-5;
      down[j].log_z -= 1e-5;
      recon::TabulateComparison(&up);
      recon::TabulateComparison(&down);
      const double slope = (up[i].probability - down[i].probability) / 2e-5;
      variance += slope * slope * rows[j].se * rows[j].se;
    }
    EXPECT_NEAR(rows[i].se_probability, std::sqrt(variance), 1e-6) << rows[i].name;
  }
  EXPECT_EQ(rows[1].verdict, "best, barely");  // 0.9 nats ahead of c
  EXPECT_EQ(rows[2].verdict, "as good");
  EXPECT_EQ(rows[0].verdict, "disfavoured");
}

TEST(ComparisonTable, AMarginWithinItsErrorIsNotDecisive) {
  // 6 nats apart but with errors of 2.5 each: ln B = −6 ± 3.5 is short of 3 errors.
  std::vector<ComparedScene> rows = {Row("a", -50.0, 2.5), Row("b", -56.0, 2.5)};
  recon::TabulateComparison(&rows);
  EXPECT_EQ(rows[0].verdict, "best, not decisive");
  EXPECT_EQ(rows[1].verdict, "disfavoured");
}

TEST(ComparisonTable, DoubtsNameWhatFailsItsBar) {
  std::vector<ComparedScene> rows = {Row("a", -50.0, 0.1), Row("b", -60.0, 0.1)};
  rows[1].agree = false;
  rows[1].ess = 40;
  rows[1].min_swap = 0.05;
  recon::TabulateComparison(&rows);
  EXPECT_TRUE(rows[0].doubts.empty());
  ASSERT_EQ(rows[1].doubts.size(), 3u);
  EXPECT_NE(rows[1].doubts[0].find("disagree"), std::string::npos);
  EXPECT_NE(rows[1].doubts[1].find("ESS 40"), std::string::npos);
  EXPECT_NE(rows[1].doubts[2].find("0.05"), std::string::npos);
  const nlohmann::json json = recon::ToJson(rows);
  EXPECT_EQ(json["scenes"].size(), 2u);
  EXPECT_EQ(json["scenes"][1]["verdict"], "rejected");
  EXPECT_EQ(json["scenes"][1]["doubts"].size(), 3u);
  EXPECT_EQ(json["likelihood"]["kappa"], 3.0);
  // 10 nats at errors of 0.14: rejected at four times the errors too, so the doubts cannot
  // change the verdict and the table does not cry wolf.
  EXPECT_TRUE(rows[1].robust);
  EXPECT_EQ(json["scenes"][1]["verdict_holds_at_wider_errors"], true);
  std::string table = recon::MarkdownTable(rows);
  EXPECT_NE(table.find("| b | -60.00 ± 0.10 |"), std::string::npos) << table;
  EXPECT_EQ(table.find("doubt"), std::string::npos) << table;
  // 6 nats at 0.71 is decisive, at four times the errors it is not: the doubts are shown.
  rows = {Row("a", -50.0, 0.5), Row("b", -56.0, 0.5)};
  rows[1].ess = 40;
  recon::TabulateComparison(&rows);
  EXPECT_EQ(rows[0].verdict, "best, decisive");
  EXPECT_EQ(rows[1].verdict, "rejected");
  EXPECT_FALSE(rows[1].robust);
  table = recon::MarkdownTable(rows);
  EXPECT_NE(table.find("rejected; doubt: ESS 40 < 200"), std::string::npos) << table;
}

TEST(ComparisonTable, RowsOfAnotherLikelihoodAreRefused) {
  std::vector<ComparedScene> rows = {Row("a", -50.0, 0.1), Row("b", -60.0, 0.1)};
  rows[1].run = "runs/b";
  EXPECT_NO_THROW(recon::CheckOneLikelihood(rows));
  rows[1].likelihood["kappa"] = 3.5;
  try {
    recon::CheckOneLikelihood(rows);
    FAIL() << "different κ accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "evidence.likelihood.kappa");
    EXPECT_EQ(e.file(), (fs::path("runs/b") / "map.json").string());
  }
  rows[1].likelihood["kappa"] = 3.0;
  rows[1].likelihood["clutter"] = true;
  EXPECT_THROW(recon::CheckOneLikelihood(rows), InputError);
}

TEST(ComparisonTable, ReadsARunsMapJson) {
  TempDir dir;
  nlohmann::json map = {
      {"log_likelihood", -1234.5},
      {"diagnosis", {{"chi2_per_dof", 1.02}}},
      {"evidence",
       {{"log_z_ss", -1300.25}, {"se_ss", 0.75}, {"log_z_ti", -1300.5}, {"se_ti", 0.8}, {"agree", true}, {"ess", 321.0},
        {"rungs", {{{"beta", 0.0}, {"swap_acceptance", 0.6}}, {{"beta", 0.5}, {"swap_acceptance", 0.31}}, {{"beta", 1.0}}}},
        {"likelihood", {{"sigma", 8.0}}}}}};
  std::ofstream(dir / "map.json") << map.dump();
  const ComparedScene row = recon::ReadComparedRun(dir.path(), "house");
  EXPECT_EQ(row.log_z, -1300.25);
  EXPECT_EQ(row.se, 0.75);
  EXPECT_EQ(row.log_z_ti, -1300.5);
  EXPECT_EQ(row.se_ti, 0.8);
  EXPECT_TRUE(row.agree);
  EXPECT_EQ(row.ess, 321.0);
  EXPECT_EQ(row.min_swap, 0.31);
  EXPECT_EQ(row.map_log_likelihood, -1234.5);
  EXPECT_EQ(row.chi2_per_dof, 1.02);
  EXPECT_EQ(row.likelihood["sigma"], 8.0);

  map.erase("evidence");
  std::ofstream(dir / "map.json") << map.dump();
  try {
    recon::ReadComparedRun(dir.path(), "house");
    FAIL() << "a run without evidence accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "evidence");
  }
  EXPECT_THROW(recon::ReadComparedRun(dir / "nowhere", "x"), InputError);
}

}  // namespace
}  // namespace vkr::test
