#pragma once
// `vkrecon run LIST -o OUT` (docs/guide/SCALE_OUT.md, "Many scenes"): the scenes of a folder (each
// immediate subfolder holding a scene.json, by name) or of a list file (one scene file or
// scene folder per line, relative to the list; blank lines and `#` comments skipped). Each
// scene gets OUT/<name>: its folder's name (for a folder or a file named scene.json), else its
// file's stem.

#include <filesystem>
#include <string>
#include <vector>

namespace vkr::recon {

struct ListedScene {
  std::string name;                // its output folder under OUT
  std::filesystem::path file;      // the scene file
};

// Whether `path` names a list of scenes rather than one scene file: a folder, or a file
// ending in .txt or .list.
bool IsSceneList(const std::filesystem::path& path);

// Throws InputError naming the list (and the line) for a missing scene, two scenes of one
// name, or an empty list.
std::vector<ListedScene> ReadSceneList(const std::filesystem::path& path);

}  // namespace vkr::recon
