// One test per bad input of docs/guide/SCENE_FORMAT.md, "Errors" (exit status 2 and one line
// naming the file, the JSON path and what is wrong): each checks file, path and problem.

#include <gtest/gtest.h>

#include "engine/scene/Scene.h"
#include "tests/scene/SceneTestUtil.h"

namespace vkr::test {
namespace {

TEST(BadInput, MalformedJsonGivesLineAndColumn) {
  TempDir dir;
  WriteText(dir / "scene.json", "{\n  \"version\": 1,,\n}");
  EXPECT_TRUE(FailsWith([&] { LoadScene(dir / "scene.json"); },
                        {"scene.json: malformed JSON", "line 2, column"}));
}

TEST(BadInput, MissingSceneFile) {
  TempDir dir;
  EXPECT_TRUE(FailsWith([&] { LoadScene(dir / "nothere.json"); },
                        {"nothere.json", "file not found"}));
}

TEST(BadInput, DuplicateKey) {
  TempDir dir;
  WriteText(dir / "scene.json",
            R"({"version": 1, "likelihood": {"sigma": 3, "sigma": 4}})");
  EXPECT_TRUE(FailsWith([&] { LoadScene(dir / "scene.json"); },
                        {"scene.json: likelihood.sigma", "twice"}));
}

TEST(BadInput, UnknownKeyTopLevel) {
  TempDir dir;
  Json scene = BaseScene();
  scene["nodez"] = Json::array();
  EXPECT_TRUE(LoadFails(dir, scene, {": nodez: unknown key 'nodez' (did you mean 'nodes'?)"}));
}

TEST(BadInput, UnknownKeyNested) {
  TempDir dir;
  Json scene = BaseScene();
  scene["nodes"][1]["primtive"] = "box";
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[1].primtive", "unknown key"}));
  scene = BaseScene();
  scene["parameters"]["w"]["inti"] = 1.0;
  EXPECT_TRUE(LoadFails(dir, scene, {"parameters.w.inti", "unknown key"}));
}

TEST(BadInput, UnknownKeyInlineCamera) {
  TempDir dir;
  Json scene = BaseScene();
  Json cam = BaseCamera("c1", "c1.pgm");
  cam["focal"] = 3;
  scene["cameras"] = Json::array({cam});
  WritePgm(dir / "c1.pgm", 4, 3);
  EXPECT_TRUE(LoadFails(dir, scene, {"cameras[0].focal", "unknown key"}));
}

TEST(BadInput, UnknownPrimitive) {
  TempDir dir;
  Json scene = BaseScene();
  scene["nodes"][1]["primitive"] = "sphere";
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[1].primitive", "unknown primitive 'sphere'"}));
  scene["nodes"][1]["primitive"] = "mesh";
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[1].primitive", "{\"mesh\": \"file.glb\"}"}));
}

TEST(BadInput, MissingMeshFile) {
  TempDir dir;
  Json scene = BaseScene();
  scene["nodes"][1]["primitive"] = Json{{"mesh", "models/m.glb"}};
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[1].primitive.mesh", "models/m.glb not found"}));
  // Present, it resolves against the scene file's folder.
  WriteText(dir / "models/m.glb", "glTF");
  const Scene s = LoadScene(WriteScene(dir, scene));
  EXPECT_EQ(s.nodes[1].primitive, PrimitiveKind::Mesh);
  EXPECT_EQ(s.nodes[1].mesh, (dir.path() / "models/m.glb").lexically_normal());
}

TEST(BadInput, MissingAlbedoFile) {
  TempDir dir;
  Json scene = BaseScene();
  scene["nodes"][1]["albedo"] = "bricks.png";
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[1].albedo", "albedo image bricks.png not found"}));
}

TEST(BadInput, MissingCameraFile) {
  TempDir dir;
  Json scene = BaseScene();
  scene["cameras"] = "cams.json";
  EXPECT_TRUE(LoadFails(dir, scene, {": cameras: camera file cams.json not found"}));
}

TEST(BadInput, MissingImage) {
  TempDir dir;
  Json scene = BaseScene();
  scene["images"] = "images";
  scene["cameras"] = Json::array({BaseCamera("c1", "c1.pgm")});
  EXPECT_TRUE(LoadFails(dir, scene, {"cameras[0].image", "images/c1.pgm not found"}));
  // synth creates the images: it loads without them.
  EXPECT_NO_THROW(LoadScene(dir / "scene.json", {}, LoadOptions{.require_images = false}));
}

TEST(BadInput, ImageSizeDiffersFromCamera) {
  TempDir dir;
  Json scene = BaseScene();
  scene["images"] = "images";
  Json cam = BaseCamera("c1", "c2.pgm");
  cam["width"] = 8;
  cam["height"] = 6;
  scene["cameras"] = Json::array({cam});
  WritePgm(dir / "images/c2.pgm", 4, 3);
  EXPECT_TRUE(LoadFails(dir, scene,
                        {"cameras[0].image: images/c2.pgm is 4×3 but the camera says 8×6"}));
}

TEST(BadInput, UnreadableImage) {
  TempDir dir;
  Json scene = BaseScene();
  scene["cameras"] = Json::array({BaseCamera("c1", "c1.pgm")});
  WriteText(dir / "c1.pgm", "hello");
  EXPECT_TRUE(LoadFails(dir, scene, {"cameras[0].image", "cannot read the size of c1.pgm"}));
}

TEST(BadInput, NonFiniteNumbers) {
  TempDir dir;
  Json scene = BaseScene();
  scene["nodes"][0]["transforms"] = Json::parse(R"([{"translate": ["1/0", 0, 0]}])");
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[0].transforms[0].translate[0]", "not finite"}));
  // An expression that is finite in general but not at the initial values (w starts at 1).
  scene = BaseScene();
  scene["nodes"][0]["transforms"] = Json::parse(R"j([{"translate": ["1/(w-1)", 0, 0]}])j");
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[0].transforms[0].translate[0]",
                                     "not finite at the initial parameter values"}));
  // A number too large for a double.
  WriteText(dir / "scene.json",
            R"({"version": 1, "nodes": [{"name": "a", "transforms": [{"scale": [1e999, 1, 1]}]}]})");
  EXPECT_TRUE(FailsWith([&] { LoadScene(dir / "scene.json"); },
                        {"scene.json", "1e999", "not a finite number"}));
  scene = BaseScene();
  scene["nodes"][0]["transforms"] = Json::parse(R"([{"translate": ["w*1e999", 0, 0]}])");
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[0].transforms[0].translate[0]",
                                     "number '1e999' in expression \"w*1e999\" is not finite"}));
}

TEST(BadInput, NonRotationR) {
  TempDir dir;
  Json scene = BaseScene();
  Json cam = BaseCamera("c1", "c1.pgm");
  cam["R"] = Json::parse("[[1, 0, 0], [0, 1, 0], [0, 0, -1]]");
  scene["cameras"] = Json::array({BaseCamera("c0", "c1.pgm"), cam});
  WritePgm(dir / "c1.pgm", 4, 3);
  EXPECT_TRUE(LoadFails(dir, scene, {"cameras[1].R: not a rotation (det -1.00"}));
  scene["cameras"][1]["R"] = Json::parse("[[1, 0.1, 0], [0, 1, 0], [0, 0, 1]]");
  EXPECT_TRUE(LoadFails(dir, scene, {"cameras[1].R: not a rotation"}));
  // Parameters cannot enter R: the pose is the way to estimate a camera.
  scene["cameras"][1]["R"] = Json::parse(R"([["w", 0, 0], [0, 1, 0], [0, 0, 1]])");
  EXPECT_TRUE(LoadFails(dir, scene, {"cameras[1].R[0][0]", "must be a constant", "pose"}));
}

TEST(BadInput, KNotUpperTriangular) {
  TempDir dir;
  Json scene = BaseScene();
  Json cam = BaseCamera("c1", "c1.pgm");
  cam["K"] = Json::parse("[[2, 0, 2], [0.1, 2, 1.5], [0, 0, 1]]");
  scene["cameras"] = Json::array({cam});
  WritePgm(dir / "c1.pgm", 4, 3);
  EXPECT_TRUE(LoadFails(dir, scene, {"cameras[0].K[1][0]", "upper triangular"}));
  scene["cameras"][0]["K"] = Json::parse("[[-2, 0, 2], [0, 2, 1.5], [0, 0, 1]]");
  EXPECT_TRUE(LoadFails(dir, scene, {"cameras[0].K", "focal lengths must be > 0"}));
}

TEST(BadInput, PriorLowNotBelowHigh) {
  TempDir dir;
  Json scene = BaseScene();
  scene["parameters"]["w"]["prior"]["uniform"] = Json::array({1.5, 0.5});
  EXPECT_TRUE(LoadFails(dir, scene, {"parameters.w.prior.uniform", "lo 1.5 must be below hi 0.5"}));
  scene["parameters"]["w"]["prior"] = Json::parse(R"({"normal": [1, 0]})");
  EXPECT_TRUE(LoadFails(dir, scene, {"parameters.w.prior.normal", "sd 0 must be > 0"}));
  scene["parameters"]["w"]["prior"] = Json::parse(R"({"normal": [1, 1]})");
  scene["parameters"]["w"]["bounds"] = Json::array({2, 2});
  EXPECT_TRUE(LoadFails(dir, scene, {"parameters.w.bounds", "must be below"}));
  scene["parameters"]["w"]["prior"] = Json::parse(R"({"cauchy": [1, 1]})");
  EXPECT_TRUE(LoadFails(dir, scene, {"parameters.w.prior.cauchy", "unknown prior"}));
}

TEST(BadInput, InitOutsidePrior) {
  TempDir dir;
  Json scene = BaseScene();
  scene["parameters"]["h"]["init"] = 3.0;
  EXPECT_TRUE(LoadFails(dir, scene, {"parameters.h.init", "outside"}));
}

TEST(BadInput, UndefinedParameter) {
  TempDir dir;
  Json scene = BaseScene();
  scene["nodes"][1]["transforms"][0]["scale"][1] = "xx+1";
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[1].transforms[0].scale[1]: unknown parameter 'xx' "
                                     "in expression \"xx+1\""}));
}

TEST(BadInput, UnusedParameter) {
  TempDir dir;
  Json scene = BaseScene();
  scene["nodes"][1]["transforms"][0]["scale"][2] = 1;  // h no longer used
  EXPECT_TRUE(LoadFails(dir, scene, {"scene.json: parameters.h: declared but used nowhere"}));
}

TEST(BadInput, CyclicParents) {
  TempDir dir;
  Json scene = BaseScene();
  scene["nodes"].push_back(Json{{"name", "a"}, {"parent", "b"}});
  scene["nodes"].push_back(Json{{"name", "b"}, {"parent", "a"}});
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[2].parent", "cyclic parents: a -> b -> a"}));
  // A node that is its own parent, reached from an earlier node: the cycle is named.
  scene["nodes"][3]["parent"] = "b";
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[3].parent", "cyclic parents: b -> b"}));
}

TEST(BadInput, UnknownParentAndChildBeforeParent) {
  TempDir dir;
  Json scene = BaseScene();
  scene["nodes"][1]["parent"] = "grund";
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[1].parent", "unknown parent 'grund'"}));
  scene = BaseScene();
  scene["nodes"][0]["parent"] = "box";
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[0].parent", "listed after this node"}));
}

TEST(BadInput, DuplicateNodeName) {
  TempDir dir;
  Json scene = BaseScene();
  scene["nodes"][1]["name"] = "ground";
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[1].name", "used twice"}));
}

TEST(BadInput, VersionAndSettings) {
  TempDir dir;
  Json scene = BaseScene();
  scene.erase("version");
  EXPECT_TRUE(LoadFails(dir, scene, {"version: missing"}));
  scene["version"] = 2;
  EXPECT_TRUE(LoadFails(dir, scene, {"version: unsupported version 2"}));
  scene["version"] = 1;
  // The settings blocks belong to their layers (tests/recon/SceneSettingsTest.cpp); here only
  // their shape.
  for (const char* block : {"likelihood", "sampler", "synth"}) {
    scene[block] = Json::array();
    EXPECT_TRUE(LoadFails(dir, scene, {std::string(block) + ": expected an object"}));
    scene.erase(block);
  }
}

TEST(BadInput, TransformSyntax) {
  TempDir dir;
  Json scene = BaseScene();
  scene["nodes"][0]["transforms"] = Json::parse(R"([{"shear": [1, 2, 3]}])");
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[0].transforms[0].shear", "unknown transform"}));
  scene["nodes"][0]["transforms"] = Json::parse(R"([{"scale": [1, 2]}])");
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[0].transforms[0].scale", "3 values"}));
  scene["nodes"][0]["transforms"] = Json::parse(R"([{"scale": [1, 2, 3], "rotate": [0, 0, 0]}])");
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[0].transforms[0]", "expected one of"}));
  scene["nodes"][0]["transforms"] = Json::parse(R"([{"scale": [1, true, 3]}])");
  EXPECT_TRUE(LoadFails(dir, scene, {"nodes[0].transforms[0].scale[1]", "expected a number"}));
}

TEST(BadInput, CameraPoseCannotScale) {
  TempDir dir;
  Json scene = BaseScene();
  Json cam = BaseCamera("c1", "c1.pgm");
  cam["pose"] = Json::parse(R"([{"scale": [2, 2, 2]}])");
  scene["cameras"] = Json::array({cam});
  WritePgm(dir / "c1.pgm", 4, 3);
  EXPECT_TRUE(LoadFails(dir, scene, {"cameras[0].pose[0].scale", "only translate and rotate"}));
}

TEST(BadInput, CameraFileErrorsNameTheCameraFile) {
  TempDir dir;
  Json scene = BaseScene();
  scene["cameras"] = "cams/cameras.json";
  Json cam = BaseCamera("c1", "c1.pgm");
  cam["R"] = Json::parse("[[0, 1, 0], [1, 0, 0], [0, 0, 1]]");
  WriteText(dir / "cams/cameras.json", Json{{"cameras", Json::array({cam})}}.dump());
  WritePgm(dir / "c1.pgm", 4, 3);
  WriteScene(dir, scene);
  EXPECT_TRUE(FailsWith([&] { LoadScene(dir / "scene.json"); },
                        {"cams/cameras.json: cameras[0].R: not a rotation (det -1.00"}));
}

}  // namespace
}  // namespace vkr::test
