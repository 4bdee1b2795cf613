#pragma once
// `vkrecon run LIST -o OUT` (docs/guide/SCALE_OUT.md, "Many scenes"): the scenes of a folder (each
// immediate subfolder holding a scene.json, by name) or of a list file (one scene file or
// scene folder per line, relative to the list; blank lines and `#` comments skipped). Each
// scene gets OUT/<name>: its folder's name (for a folder or a file named scene.json), else its
// file's stem.

#include <filesystem>
#include <string>
#include <vector>

#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "recon/Reconstruct.h"

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

// How one scene of a list ended.
enum class ListedOutcome { Ok, NotOk, ModelError, Interrupted, BadInput, Error };
const char* ToString(ListedOutcome outcome);
// `vkrecon run`'s exit status for one scene: 0 a result, 1 none or an untrustworthy one, 2 bad input.
int ExitStatus(ListedOutcome outcome);

// Many scenes (docs/guide/SCALE_OUT.md, "Many scenes"): scene i, loaded with `overrides`,
// runs on rank i mod R as a process of its own, with `base`'s options into
// base.output_dir/<name>. A scene that fails does not stop the others; should_stop stops the
// rest. Rank 0 gathers how each ended, writes OUT/summary.csv and the table to base.log, and
// returns the worst exit status; the other ranks return 0.
int ReconstructList(const std::vector<ListedScene>& scenes, const std::vector<SceneOverride>& overrides,
                    const ReconstructOptions& base, const Ranks& ranks, vk::Device& device);

}  // namespace vkr::recon
