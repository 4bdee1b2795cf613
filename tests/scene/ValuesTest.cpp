// Priors, parameters and `--at` value files.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "engine/scene/Scene.h"
#include "tests/scene/SceneTestUtil.h"

namespace vkr::test {
namespace {

TEST(Prior, UniformAndNormal) {
  const Prior uniform{Prior::Kind::Uniform, 1.0, 3.0};
  EXPECT_DOUBLE_EQ(uniform.LogDensity(2.0), -std::log(2.0));
  EXPECT_EQ(uniform.LogDensity(3.5), -std::numeric_limits<double>::infinity());
  EXPECT_EQ(uniform.Width(), 2.0);
  EXPECT_EQ(uniform.Centre(), 2.0);
  const Prior normal{Prior::Kind::Normal, 10.0, 15.0};
  EXPECT_NEAR(normal.LogDensity(25.0) - normal.LogDensity(10.0), -0.5, 1e-12);
  EXPECT_NEAR(normal.LogDensity(10.0), -std::log(15.0 * std::sqrt(2 * std::numbers::pi)), 1e-12);
  EXPECT_EQ(normal.Width(), 60.0);
  EXPECT_EQ(normal.Centre(), 10.0);
}

TEST(Parameter, InitialAndAdmissible) {
  Parameter yaw{"yaw", {Prior::Kind::Normal, 10, 15}, std::make_pair(-45.0, 5.0), std::nullopt};
  EXPECT_EQ(yaw.Initial(), 5.0);  // the prior's centre clamped into the bounds
  EXPECT_TRUE(yaw.Admissible(-45.0));
  EXPECT_FALSE(yaw.Admissible(6.0));
  EXPECT_FALSE(yaw.Admissible(std::nan("")));
  yaw.init = -3.0;
  EXPECT_EQ(yaw.Initial(), -3.0);
  const Parameter w{"w", {Prior::Kind::Uniform, 0.3, 1.5}, std::nullopt, std::nullopt};
  EXPECT_DOUBLE_EQ(w.Initial(), 0.9);
  EXPECT_FALSE(w.Admissible(1.6));
}

TEST(Values, WriteAndReadBackExactly) {
  TempDir dir;
  const Scene s = LoadScene(WriteScene(dir, BaseScene()));
  ASSERT_EQ(s.ParameterIndex("w"), 0);
  ASSERT_EQ(s.ParameterIndex("h"), 1);
  EXPECT_EQ(s.ParameterIndex("nope"), -1);
  EXPECT_EQ(s.InitialValues(), (std::vector<double>{1.0, 0.5}));
  const std::vector<double> psi = {1.0 + 1.0 / 3.0, 0.1 + 0.2};
  s.WriteValues(dir / "at.json", psi);
  EXPECT_EQ(s.ValuesFromFile(dir / "at.json"), psi);  // bit for bit
  const Json written = Json::parse(ReadText(dir / "at.json"));
  EXPECT_EQ(written.begin().key(), "w");  // parameter order
  EXPECT_EQ(written["h"].get<double>(), 0.1 + 0.2);
}

TEST(Values, BadAtFile) {
  TempDir dir;
  const Scene s = LoadScene(WriteScene(dir, BaseScene()));
  WriteText(dir / "at.json", R"({"w": 1.0})");
  EXPECT_TRUE(FailsWith([&] { s.ValuesFromFile(dir / "at.json"); },
                        {"at.json: h: missing value for parameter 'h'"}));
  WriteText(dir / "at.json", R"({"w": 1.0, "h": 0.5, "d": 2})");
  EXPECT_TRUE(FailsWith([&] { s.ValuesFromFile(dir / "at.json"); },
                        {"at.json: d: unknown parameter 'd'"}));
  WriteText(dir / "at.json", R"({"w": 7.0, "h": 0.5})");
  EXPECT_TRUE(FailsWith([&] { s.ValuesFromFile(dir / "at.json"); },
                        {"at.json: w", "outside the prior"}));
  WriteText(dir / "at.json", R"({"w": "1", "h": 0.5})");
  EXPECT_TRUE(FailsWith([&] { s.ValuesFromFile(dir / "at.json"); },
                        {"at.json: w", "expected a number"}));
  WriteText(dir / "at.json", R"({"w": 1, "h": 0.5)");
  EXPECT_TRUE(FailsWith([&] { s.ValuesFromFile(dir / "at.json"); },
                        {"at.json", "malformed JSON"}));
  WriteText(dir / "at.json", "[1, 0.5]");
  EXPECT_TRUE(FailsWith([&] { s.ValuesFromFile(dir / "at.json"); }, {"at.json", "expected an object"}));
  EXPECT_TRUE(FailsWith([&] { s.ValuesFromFile(dir / "none.json"); },
                        {"none.json", "file not found"}));
}

}  // namespace
}  // namespace vkr::test
