// Validity masks of the cameras (as in COLMAP: masks/<image name>.png, 0 = ignore). The
// rule, one for every scene
// (docs/guide/SCENE_FORMAT.md, "Masks"): the mask of the image NAME (as the camera names it,
// relative to the images folder, extension included) is FOLDER/NAME.png, with FOLDER the
// scene's `"masks"` folder or, without that key, `masks/` beside the images folder — COLMAP's
// project layout (images/ and masks/ side by side), where COLMAP's own feature extraction,
// which scans the images folder recursively, never mistakes a mask for a photograph.
// A camera whose mask file does not exist has none (every pixel counts), as in COLMAP.

#include <system_error>

#include "engine/common/InputError.h"
#include "engine/image/Image.h"
#include "engine/scene/SceneJson.h"

namespace vkr::scene_detail {

void ResolveMasks(const Json* value, const Reader& r, bool require_images, Scene& scene) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path folder;
  if (value) {
    const std::string name = r.String(*value, "masks");
    if (name.empty()) r.Fail("masks", "empty folder name");
    folder = (r.dir / name).lexically_normal();
    if (!fs::is_directory(folder, ec)) r.Fail("masks", "masks folder " + r.Display(folder) + " not found");
  } else {
    folder = (scene.images_dir.parent_path() / "masks").lexically_normal();
    if (!fs::is_directory(folder, ec)) return;
  }
  for (CameraModel& cam : scene.cameras) {
    const fs::path image = cam.image.lexically_relative(scene.images_dir);
    const fs::path mask = (folder / (image.generic_string() + ".png")).lexically_normal();
    if (!fs::is_regular_file(mask, ec)) continue;
    cam.mask = mask;
    if (!require_images) continue;  // synth and render read no photographs, nor masks
    const std::string shown = r.Display(mask);
    int w = 0, h = 0;
    try {
      ReadImageSize(mask, &w, &h);
    } catch (const InputError& e) {
      r.Fail("masks", "cannot read mask " + shown + " of camera " + cam.name + ": " + e.problem());
    }
    if (w != cam.width || h != cam.height)
      r.Fail("masks", "mask " + shown + " is " + std::to_string(w) + "×" + std::to_string(h) + " but camera " +
                          cam.name + " is " + std::to_string(cam.width) + "×" + std::to_string(cam.height));
  }
}

}  // namespace vkr::scene_detail
