#pragma once
// Writes evaluated cameras as a `cameras.json` that LoadScene reads back
// (docs/guide/SCENE_FORMAT.md, "cameras": {"cameras": [{"name", "image", "width", "height", "K",
// "R", "t"}]}), with a camera's lens as `"distortion": {"model", coefficients…}` when it has one.

#include <filesystem>
#include <vector>

#include "engine/scene/Scene.h"

namespace vkr {

// `image` of each camera is written relative to the file's folder when it lies inside it.
void WriteCamerasJson(const std::filesystem::path& file, const std::vector<Camera>& cameras);

}  // namespace vkr
