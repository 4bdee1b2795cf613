// ExpressionTable: compiled once, evaluated per hypothesis, errors named by JSON path.

#include "engine/scene/Expression.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/scene/SceneTestUtil.h"

namespace vkr::test {
namespace {

TEST(Expression, EvaluatesFormulasOverParameters) {
  ExpressionTable table({"rise", "h", "rh"}, "scene.json");
  const int twice = table.Compile("2*rise", "scene.json", "a");
  const int offset = table.Compile("0.5*h + 0.1", "scene.json", "b");
  const int ratio = table.Compile("rh/h", "scene.json", "c");
  EXPECT_DOUBLE_EQ(table.Evaluate(twice, {0.17, 2.0, 0.3}), 0.34);
  EXPECT_DOUBLE_EQ(table.Evaluate(offset, {0.17, 2.0, 0.3}), 1.1);
  EXPECT_DOUBLE_EQ(table.Evaluate(ratio, {0.17, 2.0, 0.3}), 0.15);
  // The same compiled expressions at another hypothesis: values are rebound, not cached.
  EXPECT_DOUBLE_EQ(table.Evaluate(ratio, {0.0, 0.5, 0.4}), 0.8);
  EXPECT_DOUBLE_EQ(table.Evaluate(twice, {-1.0, 0.5, 0.4}), -2.0);
  EXPECT_EQ(table.UsedParameters(ratio), (std::vector<int>{1, 2}));
  EXPECT_TRUE(table.IsUsed(0));
  EXPECT_EQ(table.Field(offset), "b");
  EXPECT_EQ(table.Text(offset), "0.5*h + 0.1");
}

TEST(Expression, DivisionByZeroIsAValueNotAnException) {
  ExpressionTable table({"h"}, "scene.json");
  const int id = table.Compile("1/h", "scene.json", "x");
  EXPECT_TRUE(std::isinf(table.Evaluate(id, {0.0})));
}

TEST(Expression, UnknownNameIsNamedWithItsPath) {
  ExpressionTable table({"x"}, "scene.json");
  EXPECT_TRUE(FailsWith(
      [&] { table.Compile("xx+1", "scene.json", "nodes[1].transforms[0].translate[0]"); },
      {"scene.json: nodes[1].transforms[0].translate[0]: unknown parameter 'xx' in expression "
       "\"xx+1\""}));
}

TEST(Expression, SyntaxErrorCarriesMuParserMessage) {
  ExpressionTable table({"w"}, "scene.json");
  EXPECT_TRUE(FailsWith([&] { table.Compile("2*(w", "scene.json", "nodes[0].x"); },
                        {"scene.json", "nodes[0].x", "cannot parse expression \"2*(w\"",
                         "parenthes"}));
  EXPECT_TRUE(FailsWith([&] { table.Compile("w +* 2", "scene.json", "f"); },
                        {"cannot parse expression"}));
  EXPECT_TRUE(FailsWith([&] { table.Compile("  ", "scene.json", "f"); }, {"empty expression"}));
}

TEST(Expression, AssignmentAndListsAreRefused) {
  ExpressionTable table({"w"}, "scene.json");
  EXPECT_TRUE(FailsWith([&] { table.Compile("w=3", "scene.json", "f"); }, {"assigns"}));
  EXPECT_TRUE(FailsWith([&] { table.Compile("w+=3", "scene.json", "f"); }, {"assigns"}));
  EXPECT_TRUE(FailsWith([&] { table.Compile("w, 2", "scene.json", "f"); }, {"several"}));
  // Comparisons are not assignments.
  const int id = table.Compile("w >= 1 ? 2 : 3", "scene.json", "f");
  EXPECT_EQ(table.Evaluate(id, {1.5}), 2.0);
  EXPECT_EQ(table.Evaluate(id, {0.5}), 3.0);
}

TEST(Expression, BadParameterNames) {
  EXPECT_TRUE(FailsWith([] { ExpressionTable({"sin"}, "scene.json"); },
                        {"scene.json: parameters.sin", "built-in function"}));
  EXPECT_TRUE(FailsWith([] { ExpressionTable({"2w"}, "scene.json"); },
                        {"parameters.2w", "cannot be a parameter name"}));
  EXPECT_TRUE(FailsWith([] { ExpressionTable({"_pi"}, "scene.json"); }, {"parameters._pi"}));
}

TEST(Expression, ConstantExpressions) {
  EXPECT_DOUBLE_EQ(EvaluateConstantExpression("0.5*sqrt(4)", "f.json", "R[0][0]", "why"), 1.0);
  EXPECT_TRUE(FailsWith([] { EvaluateConstantExpression("w", "f.json", "R[0][0]", "R is fixed"); },
                        {"f.json: R[0][0]", "reads 'w'", "R is fixed"}));
  EXPECT_TRUE(FailsWith([] { EvaluateConstantExpression("1/0", "f.json", "t[1]", ""); },
                        {"f.json: t[1]", "not finite"}));
}

TEST(Expression, SceneExpressionsAndFolding) {
  TempDir dir;
  Json scene = BaseScene();
  scene["parameters"]["rise"] = Json::parse(R"({"prior": {"uniform": [0.1, 0.2]}})");
  scene["nodes"][1]["transforms"] = Json::parse(
      R"j([{"translate": ["2*rise", "0.5*h + 0.1", "2*sqrt(4)"]}, {"scale": ["w", 1, "h"]}])j");
  const Scene s = LoadScene(WriteScene(dir, scene));
  const Transform& t = s.nodes[1].transforms[0];
  EXPECT_FALSE(t.value[0].IsConstant());
  EXPECT_FALSE(t.value[1].IsConstant());
  // A parameter-free expression becomes a constant: no per-hypothesis cost.
  ASSERT_TRUE(t.value[2].IsConstant());
  EXPECT_EQ(t.value[2].constant, 4.0);
  const std::vector<double> psi = {1.0, 0.6, 0.15};  // w, h, rise (file order)
  EXPECT_DOUBLE_EQ(s.Evaluate(t.value[0], psi), 0.3);
  EXPECT_DOUBLE_EQ(s.Evaluate(t.value[1], psi), 0.4);
}

TEST(Expression, UnusedParameterIsAnError) {
  TempDir dir;
  Json scene = BaseScene();
  scene["parameters"]["q"] = Json::parse(R"({"prior": {"normal": [0, 1]}})");
  EXPECT_TRUE(LoadFails(dir, scene, {"parameters.q", "used nowhere"}));
}

TEST(Expression, ParameterUsedOnlyByACameraCounts) {
  TempDir dir;
  Json scene = BaseScene();
  scene["parameters"]["f"] = Json::parse(R"({"prior": {"uniform": [1.5, 2.5]}})");
  Json cam = BaseCamera("c1", "c1.pgm");
  cam["K"] = Json::parse(R"([["f", 0, 2], [0, "f", 1.5], [0, 0, 1]])");
  scene["cameras"] = Json::array({cam});
  WritePgm(dir / "c1.pgm", 4, 3);
  const Scene s = LoadScene(WriteScene(dir, scene));
  const auto cams = s.Cameras({1.0, 0.5, 2.25});
  EXPECT_EQ(cams[0].K(0, 0), 2.25);
  EXPECT_EQ(cams[0].K(1, 1), 2.25);
  EXPECT_EQ(cams[0].K(0, 2), 2.0);
}

}  // namespace
}  // namespace vkr::test
