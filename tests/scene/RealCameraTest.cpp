// Cameras of real photographs in scene and camera files (docs/guide/SCENE_FORMAT.md, "cameras"):
// the `distortion` entry is read or refused — never dropped, even in camera files whose other
// unknown keys are ignored — written back by CameraWriter, and masks are found by the one folder
// rule of docs/guide/SCENE_FORMAT.md ("Masks") and checked like images.

#include <gtest/gtest.h>

#include "engine/scene/CameraWriter.h"
#include "tests/scene/SceneTestUtil.h"

namespace vkr::test {
namespace {

Json Opencv() { return Json{{"model", "OPENCV"}, {"k1", -0.12}, {"k2", 0.03}, {"p1", 0.001}, {"p2", -0.002}}; }

// A scene whose one camera (c1.pgm, 4×3) comes from a camera file carrying `distortion`.
std::filesystem::path SceneWithCameraFile(const TempDir& dir, const Json& distortion) {
  Json cam = BaseCamera("c1", "c1.pgm");
  cam["distortion"] = distortion;
  WriteText(dir / "cameras.json", Json{{"cameras", Json::array({cam})}}.dump());
  WritePgm(dir / "c1.pgm", 4, 3);
  Json scene = BaseScene();
  scene["cameras"] = "cameras.json";
  return WriteScene(dir, scene);
}

TEST(CameraDistortion, ReadFromCameraFilesAndInlineCameras) {
  TempDir dir;
  const Scene s = LoadScene(SceneWithCameraFile(dir, Opencv()));
  const LensDistortion& d = s.cameras[0].distortion;
  EXPECT_EQ(d.model, DistortionModel::OpenCV);
  EXPECT_EQ(d.Coefficient("k1"), -0.12);
  EXPECT_EQ(d.Coefficient("p2"), -0.002);
  EXPECT_EQ(s.Cameras(s.InitialValues())[0].distortion.coefficients, d.coefficients);

  // Inline, FULL_OPENCV adds k3…k6; the radial-only models by their COLMAP names; constant
  // expressions are constants.
  Json scene = BaseScene();
  Json full = Opencv();
  full["model"] = "FULL_OPENCV";
  for (const char* k : {"k3", "k4", "k5", "k6"}) full[k] = 0.01;
  Json a = BaseCamera("a", "c1.pgm"), b = BaseCamera("b", "c1.pgm"), c = BaseCamera("c", "c1.pgm");
  a["distortion"] = full;
  b["distortion"] = Json{{"model", "SIMPLE_RADIAL"}, {"k", "-0.1/2"}};
  c["distortion"] = Json{{"model", "RADIAL"}, {"k1", -0.1}, {"k2", 0.02}};
  scene["cameras"] = Json::array({a, b, c});
  const Scene inline_scene = LoadScene(WriteScene(dir, scene));
  EXPECT_EQ(inline_scene.cameras[0].distortion.Coefficient("k6"), 0.01);
  EXPECT_EQ(inline_scene.cameras[1].distortion.Coefficient("k"), -0.05);
  EXPECT_EQ(inline_scene.cameras[2].distortion.model, DistortionModel::Radial);
}

// Each malformed `distortion` stops with one line naming the camera file, the JSON path
// and the problem — in a camera file, where other unknown keys are ignored.
TEST(CameraDistortion, MalformedIsAnInputErrorNamingThePath) {
  struct Case {
    Json distortion;
    std::vector<std::string> parts;
  };
  Json missing = Opencv();
  missing.erase("p2");
  Json extra = Opencv();
  extra["k3"] = 0.1;
  Json expression = Opencv();
  expression["k1"] = "w";
  Json nan_text = Opencv();
  nan_text["k2"] = "1/0";
  const std::vector<Case> cases = {
      {Json{{"model", "OPENCV_FISHEYE"}, {"k1", 0}},
       {"cameras[0].distortion.model", "unknown distortion model 'OPENCV_FISHEYE'", "SIMPLE_RADIAL, RADIAL, OPENCV, FULL_OPENCV"}},
      {Json{{"k1", 0.1}}, {"cameras[0].distortion.model", "missing"}},
      {missing, {"cameras[0].distortion.p2", "missing (OPENCV takes k1, k2, p1, p2)"}},
      {extra, {"cameras[0].distortion.k3", "OPENCV has no coefficient 'k3'"}},
      {expression, {"cameras[0].distortion.k1", "reads 'w'", "lens distortion is constant"}},
      {nan_text, {"cameras[0].distortion.k2", "not finite"}},
      {Json::array({-0.1, 0.01}), {"cameras[0].distortion", "expected {\"model\""}},
      {Json{{"model", "OPENCV"}, {"k1", "x"}, {"k2", 0}, {"p1", 0}, {"p2", 0}}, {"cameras[0].distortion.k1"}},
  };
  for (const Case& c : cases) {
    TempDir dir;
    const auto file = SceneWithCameraFile(dir, c.distortion);
    std::vector<std::string> parts = c.parts;
    parts.push_back("cameras.json: ");
    EXPECT_TRUE(FailsWith([&] { LoadScene(file); }, parts)) << c.distortion.dump();
  }
}

TEST(CameraDistortion, NeedsAConstantK) {
  TempDir dir;
  Json scene = BaseScene();
  Json cam = BaseCamera("c1", "c1.pgm");
  cam["K"][0][0] = "2*w";
  cam["distortion"] = Opencv();
  scene["cameras"] = Json::array({cam});
  WritePgm(dir / "c1.pgm", 4, 3);
  EXPECT_TRUE(LoadFails(dir, scene, {"cameras[0].K[0][0]", "lens distortion needs a constant K"}));
}

// synth writes what it renders through (CameraWriter), and LoadScene reads it back.
TEST(CameraDistortion, CameraWriterRoundTrips) {
  TempDir dir;
  const Scene s = LoadScene(SceneWithCameraFile(dir, Opencv()));
  std::vector<Camera> cams = s.Cameras(s.InitialValues());
  std::filesystem::create_directories(dir / "out");
  WriteCamerasJson(dir / "out/cameras.json", cams);
  Json scene = BaseScene();
  scene["cameras"] = "out/cameras.json";
  const Scene back = LoadScene(WriteScene(dir, scene, "again.json"), {}, LoadOptions{false});
  EXPECT_EQ(back.cameras[0].distortion.model, DistortionModel::OpenCV);
  EXPECT_EQ(back.cameras[0].distortion.coefficients, cams[0].distortion.coefficients);
  // A pinhole camera is written without the key.
  cams[0].distortion = LensDistortion{};
  WriteCamerasJson(dir / "out/cameras.json", cams);
  EXPECT_EQ(ReadText(dir / "out/cameras.json").find("distortion"), std::string::npos);
}

// ---- masks ----

Json MaskScene(const std::string& images) {
  Json scene = BaseScene();
  scene["images"] = images;
  scene["cameras"] = Json::array({BaseCamera("c1", "c1.pgm"), BaseCamera("c2", "sub/c2.pgm")});
  return scene;
}

TEST(Masks, BesideTheImagesFolderAsInColmap) {
  TempDir dir;
  WritePgm(dir / "images/c1.pgm", 4, 3);
  WritePgm(dir / "images/sub/c2.pgm", 4, 3);
  WritePgm(dir / "masks/c1.pgm.png", 4, 3);  // any image format; the name adds .png to the image's
  const Scene s = LoadScene(WriteScene(dir, MaskScene("images")));
  EXPECT_EQ(s.cameras[0].mask, (dir.path() / "masks/c1.pgm.png").lexically_normal());
  EXPECT_TRUE(s.cameras[1].mask.empty()) << "no mask file: every pixel counts";
  WritePgm(dir / "masks/sub/c2.pgm.png", 4, 3);
  EXPECT_EQ(LoadScene(dir / "scene.json").cameras[1].mask, (dir.path() / "masks/sub/c2.pgm.png").lexically_normal());
}

TEST(Masks, FolderNamedInTheScene) {
  TempDir dir;
  WritePgm(dir / "images/c1.pgm", 4, 3);
  WritePgm(dir / "images/sub/c2.pgm", 4, 3);
  WritePgm(dir / "masks/c1.pgm.png", 4, 3);  // not the default folder's: "masks" replaces it
  WritePgm(dir / "mine/sub/c2.pgm.png", 4, 3);
  Json scene = MaskScene("images");
  scene["masks"] = "mine";
  const Scene s = LoadScene(WriteScene(dir, scene));
  EXPECT_TRUE(s.cameras[0].mask.empty());
  EXPECT_EQ(s.cameras[1].mask, (dir.path() / "mine/sub/c2.pgm.png").lexically_normal());
  scene["masks"] = "nowhere";
  EXPECT_TRUE(LoadFails(dir, scene, {"scene.json: masks: masks folder nowhere not found"}));
  scene["mask"] = "mine";
  scene.erase("masks");
  EXPECT_TRUE(LoadFails(dir, scene, {"scene.json: mask: unknown key 'mask' (did you mean 'masks'?)"}));
}

TEST(Masks, WrongSizeOrUnreadableIsAnInputError) {
  TempDir dir;
  WritePgm(dir / "images/c1.pgm", 4, 3);
  WritePgm(dir / "images/sub/c2.pgm", 4, 3);
  WritePgm(dir / "masks/c1.pgm.png", 5, 3);
  EXPECT_TRUE(LoadFails(dir, MaskScene("images"), {"scene.json: masks: mask", "c1.pgm.png is 5×3 but camera c1 is 4×3"}));
  WriteText(dir / "masks/c1.pgm.png", "not an image");
  EXPECT_TRUE(LoadFails(dir, MaskScene("images"), {"scene.json: masks: cannot read mask", "of camera c1"}));
  // synth and render read no photographs: neither their masks.
  const Scene s = LoadScene(dir / "scene.json", {}, LoadOptions{false});
  EXPECT_FALSE(s.cameras[0].mask.empty());
}

}  // namespace
}  // namespace vkr::test
