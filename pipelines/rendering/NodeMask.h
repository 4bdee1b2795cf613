#pragma once
// Masks of chosen nodes for `vkrecon synth --mask-nodes` (docs/guide/SCENE_FORMAT.md, "Masks"):
// the pixels where an object that a model will leave out (an occluder, a passer-by) is
// the visible surface, so that a reconstruction can ignore them as COLMAP's masks do.

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "engine/image/Image.h"
#include "engine/scene/Scene.h"

namespace vkr {

// Indices of the nodes named in `names` (a comma-separated list is split). Throws
// InputError("", option, …) for a name that is no node of the scene.
std::vector<int> NodeIndices(const Scene& scene, const std::vector<std::string>& names, const std::string& option);

// 0 (all channels) where one of `nodes` is the visible surface, 1 elsewhere. `positions`
// renders the scene's world positions with the given node matrices (alpha 1 on the
// surface; NovelViewPass::Output::WorldPosition). The nodes are hidden by collapsing their
// matrices (their children stay), and a pixel is masked where hiding them changes what it
// sees: they covered it, whatever lies behind (the background included).
Image VisibleNodeMask(const std::function<Image(const std::vector<Eigen::Matrix4d>&)>& positions,
                      const std::vector<Eigen::Matrix4d>& world_from_node, const std::vector<int>& nodes);

// Writes a mask as an 8-bit PNG: 0 where `mask` is below ½, 255 elsewhere.
void WriteMaskPng(const std::filesystem::path& file, const Image& mask);

}  // namespace vkr
