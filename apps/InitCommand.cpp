// `vkrecon init SPARSE -o SCENE`: parses the options and calls recon::InitScene.

#include <iostream>
#include <locale>
#include <sstream>

#include "apps/Commands.h"
#include "engine/common/InputError.h"
#include "recon/SceneInit.h"

namespace vkr::app {
namespace {

Eigen::Vector3d ParseUp(const std::string& text) {
  std::istringstream in(text);
  in.imbue(std::locale::classic());
  Eigen::Vector3d up;
  char c1 = 0, c2 = 0;
  if (!(in >> up.x() >> c1 >> up.y() >> c2 >> up.z()) || c1 != ',' || c2 != ',' || !(in >> std::ws).eof())
    throw InputError("", "--up", "expected X,Y,Z (a direction in the COLMAP model's frame), not '" + text + "'");
  return up;
}

}  // namespace

int RunInit(int argc, char** argv) {
  CLI::App app(
      "Make a scene folder from a COLMAP sparse model (binary or text: cameras, images, points3D). Finds the "
      "ground, a plane through the triangulated points near the cameras' mean up direction (or --up), and "
      "writes SCENE/cameras.json in a Z-up frame: the ground at z = 0, the origin under the centre of the "
      "points above it, +x along their footprint's principal axis. Lengths stay in COLMAP's arbitrary units "
      "unless --scale-points gives one known length. Also writes SCENE/points.ply (the points in that frame), "
      "a starter SCENE/scene.json from --template whose priors bracket the points above the ground, with "
      "\"images\" (and \"masks\", when the photographs have a masks/ folder beside them) wired, and "
      "SCENE/init.json (the settings and the transform). Bad input (no points, one image, no ground, a "
      "template the points do not fit, a photograph missing) exits 2 with one line. docs/guide/REAL_PHOTOS.md.",
      "init");
  recon::InitOptions options;
  std::string sparse, output, images, template_name = "box", up, scale_points;
  app.add_option("sparse", sparse, "the COLMAP model's folder, e.g. project/sparse/0")->required();
  app.add_option("-o,--output", output, "the scene folder to write (it must not hold a scene.json)")->required();
  app.add_option("--images", images,
                 "the photographs the model's image names are relative to (default: SPARSE/../images, or "
                 "SPARSE/../../images for project/sparse/0)");
  app.add_option("--template", template_name, "the starter scene: box (x y yaw w d h), house (walls and a roof: + rh), cylinder (x y diameter height), stairs (four steps: x y yaw width run rise) or corner (two walls meeting in an inside corner the cameras look into: xc yc yaw angle h)")
      ->capture_default_str();
  app.add_option("--up", up, "X,Y,Z: up in the model's frame, instead of the cameras' mean up (COLMAP: -y of the images)");
  app.add_option("--scale-points", scale_points,
                 "ID1,ID2=LENGTH: two POINT3D_IDs (as in points3D, see points.ply's order) and their distance in "
                 "metres; without it the scene keeps the model's units");
  app.add_option("--seed", options.seed, "the ground's RANSAC seed")->capture_default_str();
  app.add_option("--max-side", options.max_side,
                 "photographs larger than this many pixels on their longer side are used shrunk by an integer "
                 "factor (the scene's \"max_side\"); 0 uses them as they are")
      ->capture_default_str();
  if (auto status = Parse(app, argc, argv)) return *status;
  if (options.max_side != 0 && (options.max_side < 16 || options.max_side > (1 << 16)))
    throw InputError("", "--max-side", "expected 0 (none) or 16 to 65536, not " + std::to_string(options.max_side));
  options.sparse = sparse;
  options.output = output;
  options.images = images;
  if (!recon::FromString(template_name, &options.template_kind))
    throw InputError("", "--template", "unknown template '" + template_name + "' (box, house, cylinder, stairs, corner)");
  if (!up.empty()) options.up = ParseUp(up);
  if (!scale_points.empty()) options.scale = recon::ParseScalePoints(scale_points);
  const recon::InitResult result = recon::InitScene(options);
  std::cout << result.BriefReport();
  return 0;
}

}  // namespace vkr::app
