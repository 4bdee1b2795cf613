#include "pipelines/rendering/NodeMask.h"

#include <algorithm>
#include <sstream>

#include "engine/common/InputError.h"

namespace vkr {

std::vector<int> NodeIndices(const Scene& scene, const std::vector<std::string>& names, const std::string& option) {
  std::vector<int> out;
  for (const std::string& list : names) {
    std::istringstream items(list);
    for (std::string name; std::getline(items, name, ',');) {
      const auto it = std::find_if(scene.nodes.begin(), scene.nodes.end(),
                                   [&](const Node& n) { return n.name == name; });
      if (it == scene.nodes.end()) {
        std::string known;
        for (const Node& n : scene.nodes) known += (known.empty() ? "" : ", ") + n.name;
        throw InputError("", option, "no node named '" + name + "' (nodes: " + known + ")");
      }
      out.push_back(int(it - scene.nodes.begin()));
    }
  }
  return out;
}

Image VisibleNodeMask(const std::function<Image(const std::vector<Eigen::Matrix4d>&)>& positions,
                      const std::vector<Eigen::Matrix4d>& world_from_node, const std::vector<int>& nodes) {
  std::vector<Eigen::Matrix4d> hidden = world_from_node;
  for (int n : nodes) {
    // Every vertex at the origin: zero-area triangles draw no fragment.
    hidden.at(size_t(n)).setZero();
    hidden[size_t(n)](3, 3) = 1.0;
  }
  const Image without = positions(hidden);
  const Image with = positions(world_from_node);
  Image mask(with.width, with.height, 1.0f);
  for (int y = 0; y < with.height; ++y)
    for (int x = 0; x < with.width; ++x) {
      // The same rasterisation of the same triangles gives the same bits where the hidden
      // nodes were not in front; a tolerance would only blur that.
      const float* a = with.At(x, y);
      const float* b = without.At(x, y);
      if (!std::equal(a, a + 4, b)) std::fill(mask.At(x, y), mask.At(x, y) + 4, 0.0f);
    }
  return mask;
}

void WriteMaskPng(const std::filesystem::path& file, const Image& mask) {
  Image out(mask.width, mask.height, 1.0f);
  for (int y = 0; y < mask.height; ++y)
    for (int x = 0; x < mask.width; ++x) {
      float* o = out.At(x, y);
      o[0] = o[1] = o[2] = mask.At(x, y)[0] < 0.5f ? 0.0f : 1.0f;
    }
  std::filesystem::create_directories(file.parent_path());
  WritePng(file, out);
}

}  // namespace vkr
