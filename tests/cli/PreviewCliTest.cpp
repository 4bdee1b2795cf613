// `vkrecon preview` as a user meets it: an overlay per photograph, drawn where the scene is;
// a page that headless Chromium opens without error, whose JavaScript port of the scene
// (transforms, expressions, lens) reproduces vkrecon's pixels, whose sliders move the
// wireframe, whose saved values `vkrecon likelihood` accepts and whose saved scene starts at
// them; and bad input exits 2.

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>

#include "engine/image/Image.h"
#include "engine/scene/Photographs.h"
#include "tests/cli/CliTestUtil.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;
using test::Quote;
using test::RunCommand;

const std::string kVkrecon = VKRECON_BINARY;
const fs::path kBox = fs::path(VKRECON_SOURCE_DIR) / "assets/box";

// The box with its transform written as expressions (the page must evaluate them as muParser
// does) and quarter-size photographs through a distorting lens, previewed at values off the
// scene's init, with a turned box so the rotation counts. `max_side` halves the photographs
// again, so the page's K is the shrunk camera's.
class PreviewCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<test::TempDir>();
    const test::TempDir& dir = *dir_;
    nlohmann::json scene = nlohmann::json::parse(test::ReadText(kBox / "scene.json"));
    scene["nodes"][1]["transforms"] = nlohmann::json::parse(
        R"json([{"translate": ["x", "y", "0"]}, {"rotate": [0, 0, "yaw/2"]}, {"rotate": [0, 0, "-2^2/-4 * yaw/2"]},
            {"scale": ["w", "max(d, 0.1)", "h > 0 ? sqrt(h^2) : 1"]}])json");
    for (auto& node : scene["nodes"]) node["albedo"] = (kBox / node["albedo"].get<std::string>()).string();
    scene["cameras"] = (dir / "images/cameras.json").string();
    scene["images"] = (dir / "images").string();
    scene["likelihood"]["atlas"] = 64;
    scene["likelihood"]["levels"] = 1;
    scene["max_side"] = 80;
    test::WriteText(dir / "scene.json", scene.dump(2));
    test::WriteText(dir / "at.json", R"({"x": 0.1, "y": -0.05, "yaw": 17, "w": 0.8, "d": 0.7, "h": 0.5})");
    synth_ = RunCommand(kVkrecon + " synth -q " + Quote(kBox / "scene.json") + " --at " + Quote(kBox / "truth.json") +
                        " --scale 0.25 --distortion OPENCV:k1=-0.12,k2=0.03,p1=0.001 -o " + Quote(dir / "images"));
    if (synth_.exit_status != 0) return;
    preview_ = RunCommand(kVkrecon + " preview " + Quote(dir / "scene.json") + " --at " + Quote(dir / "at.json") +
                          " -o " + Quote(dir / "preview"));
  }
  static void TearDownTestSuite() { dir_.reset(); }
  void SetUp() override {
    ASSERT_EQ(synth_.exit_status, 0) << synth_.err;
    ASSERT_EQ(preview_.exit_status, 0) << preview_.err;
  }
  static fs::path dir() { return dir_->path(); }

  // The page in headless Chromium (scripts/report_screenshot.sh) with `fragment`; its DOM,
  // or nothing when Chromium is missing (the test then skips).
  static std::optional<std::string> OpenPage(const std::string& fragment, const std::string& name) {
    const auto r = RunCommand(Quote(fs::path(VKRECON_SOURCE_DIR) / "scripts/report_screenshot.sh") + " " +
                              Quote((dir() / "preview/preview.html").string() + fragment) + " " +
                              Quote(dir() / (name + ".png")) + " " + Quote(dir() / (name + ".html")));
    if (r.exit_status == 77) return std::nullopt;
    EXPECT_EQ(r.exit_status, 0) << r.err;
    return test::ReadText(dir() / (name + ".html"));
  }

  static std::unique_ptr<test::TempDir> dir_;
  static test::CommandResult synth_, preview_;
};
std::unique_ptr<test::TempDir> PreviewCli::dir_;
test::CommandResult PreviewCli::synth_, PreviewCli::preview_;

std::string Attribute(const std::string& dom, const std::string& pattern) {
  std::smatch m;
  return std::regex_search(dom, m, std::regex(pattern)) ? m[1].str() : std::string();
}

// The text of a DOM dump's element: Chromium escapes &, < and > (the expressions hold them).
std::string Unescape(std::string text) {
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"&lt;", "<"}, {"&gt;", ">"}, {"&amp;", "&"}})
    for (size_t at = 0; (at = text.find(from, at)) != std::string::npos; at += to.size()) text.replace(at, from.size(), to);
  return text;
}

TEST_F(PreviewCli, WritesAnOverlayPerPhotographAndTheValuesDrawn) {
  const nlohmann::json cameras = nlohmann::json::parse(test::ReadText(dir() / "images/cameras.json"));
  int cameras_seen = 0;
  for (const fs::path& photo : fs::directory_iterator(dir() / "images")) {
    if (photo.extension() != ".png") continue;
    ++cameras_seen;
    const fs::path overlay = dir() / "preview/overlays" / photo.filename();
    ASSERT_TRUE(fs::exists(overlay)) << overlay;
    // The overlay is at the size the scene works at: max_side 80 halves the 160 × 120 photograph.
    const Image a = LoadPhotograph(photo, 2), b = LoadImage(overlay);
    ASSERT_EQ(a.width, 80);
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    size_t changed = 0;
    for (size_t i = 0; i < a.rgba.size(); ++i) changed += std::abs(a.rgba[i] - b.rgba[i]) > 0.05f;
    EXPECT_GT(changed, size_t(a.width)) << overlay << ": the wireframe changes too few pixels";
  }
  EXPECT_GT(cameras_seen, 1);
  EXPECT_EQ(nlohmann::json::parse(test::ReadText(dir() / "preview/at.json")),
            nlohmann::json::parse(test::ReadText(dir() / "at.json")));
  const std::string html = test::ReadText(dir() / "preview/preview.html");
  for (const char* fetch : {"src=\"http", "href=\"http", "src=\"//", "<link"})
    EXPECT_EQ(html.find(fetch), std::string::npos) << fetch << ": the page must open without a network";
}

TEST_F(PreviewCli, BrowserPortAgreesAndASliderMovesTheWireframe) {
  const std::optional<std::string> still = OpenPage("", "still");
  if (!still) GTEST_SKIP() << "chromium is not installed (scripts/bootstrap.sh report)";
  // The page's own check: every camera's vertices land on vkrecon's pixels (else a console error).
  const std::string check = Attribute(*still, "data-preview-check=\"(\\d+) points");
  ASSERT_FALSE(check.empty()) << "the page did not run its check";
  EXPECT_GE(std::stoi(check), 9) << "too few check points";
  const std::string before = Attribute(*still, "<path class=\"current\" d=\"([^\"]*)\"");
  ASSERT_GT(before.size(), 100u) << "no wireframe drawn";

  const std::optional<std::string> moved = OpenPage("#w=1.3&yaw=-20", "moved");
  ASSERT_TRUE(moved);
  const std::string after = Attribute(*moved, "<path class=\"current\" d=\"([^\"]*)\"");
  EXPECT_NE(before, after) << "moving the sliders did not move the wireframe";
  std::smatch m;
  ASSERT_TRUE(std::regex_search(*moved, m, std::regex("<pre id=\"at-json\">([^<]*)</pre>")));
  const nlohmann::json saved = nlohmann::json::parse(Unescape(m[1].str()));
  EXPECT_NEAR(saved["w"].get<double>(), 1.3, 1e-2);
  EXPECT_NEAR(saved["yaw"].get<double>(), -20.0, 0.1);
  EXPECT_DOUBLE_EQ(saved["x"].get<double>(), 0.1);
  test::WriteText(dir() / "saved.json", saved.dump());
  const auto r = RunCommand(kVkrecon + " likelihood " + Quote(dir() / "scene.json") + " --at " + Quote(dir() / "saved.json"));
  EXPECT_EQ(r.exit_status, 0) << r.err;

  // The saved scene starts where the sliders were: previewed again, it draws at those values.
  ASSERT_TRUE(std::regex_search(*moved, m, std::regex("<pre id=\"scene-json\">([^<]*)</pre>")));
  test::WriteText(dir() / "saved_scene.json", Unescape(m[1].str()));
  const auto again = RunCommand(kVkrecon + " preview " + Quote(dir() / "saved_scene.json") + " -o " + Quote(dir() / "again"));
  ASSERT_EQ(again.exit_status, 0) << again.err;
  EXPECT_EQ(nlohmann::json::parse(test::ReadText(dir() / "again/at.json")), saved);
}

TEST(PreviewCliInput, MissingPhotographIsBadInput) {
  test::TempDir dir;
  fs::create_directories(dir / "empty");
  const auto r = RunCommand(kVkrecon + " preview " + Quote(kBox / "scene.json") + " --set images=" + Quote(dir / "empty") +
                            " -o " + Quote(dir / "out"));
  test::ExpectBadInput(r, {"cam0.png", "not found"});
}

TEST_F(PreviewCli, AtFileWithAnUnknownParameterIsBadInput) {
  test::WriteText(dir() / "bad_at.json", R"({"x": 0, "y": 0, "yaw": 0, "w": 1, "d": 1, "h": 0.5, "roof": 1})");
  const auto r = RunCommand(kVkrecon + " preview " + Quote(dir() / "scene.json") + " --at " +
                            Quote(dir() / "bad_at.json") + " -o " + Quote(dir() / "bad"));
  test::ExpectBadInput(r, {(dir() / "bad_at.json").string(), "roof", "unknown parameter"});
  EXPECT_FALSE(fs::exists(dir() / "bad/preview.html"));
}

// A typo in a settings block is caught before a run, as `run` and `synth` would: one line
// naming the file and the field, and no page written.
TEST_F(PreviewCli, SettingsTypoIsBadInput) {
  for (const auto& [set, words] :
       {std::pair<std::string, std::vector<std::string>>{"likelihood.atlass=64", {"likelihood.atlass", "atlas"}},
        {"sampler.chains=two", {"sampler.chains"}},
        {"synth.exposur=1", {"synth.exposur"}}}) {
    SCOPED_TRACE(set);
    const auto r = RunCommand(kVkrecon + " preview " + Quote(dir() / "scene.json") + " --set " + set + " -o " +
                              Quote(dir() / "typo"));
    std::vector<std::string> expected = {(dir() / "scene.json").string()};
    expected.insert(expected.end(), words.begin(), words.end());
    test::ExpectBadInput(r, expected);
    EXPECT_FALSE(fs::exists(dir() / "typo/preview.html"));
  }
}

TEST(PreviewCliInput, HelpExplainsTheCommand) {
  const auto r = RunCommand(kVkrecon + " preview --help");
  EXPECT_EQ(r.exit_status, 0);
  for (const char* word : {"--at", "slider", "lens", "preview.html"}) EXPECT_NE(r.out.find(word), std::string::npos) << word;
}

}  // namespace
}  // namespace vkr
