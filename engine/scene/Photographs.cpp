#include "engine/scene/Photographs.h"

#include <algorithm>

#include "engine/image/Pyramid.h"

namespace vkr {

int ShrinkFactor(int width, int height, int max_side) {
  const int side = std::max(width, height);
  if (max_side <= 0 || side <= max_side) return 1;
  return (side + max_side - 1) / max_side;
}

Image LoadPhotograph(const std::filesystem::path& file, int shrink) { return BoxShrink(LoadImage(file), shrink); }

Image LoadMask(const std::filesystem::path& file, int shrink) {
  Image mask = LoadImage(file);
  if (shrink <= 1) return mask;
  // A pixel keeps when any colour channel is nonzero (as LensWarp reads masks): 1 or 0 first,
  // then the mean is 1 only where every pixel kept (up to float rounding).
  for (size_t i = 0; i < mask.rgba.size(); i += 4) {
    const float keep = mask.rgba[i] > 0.0f || mask.rgba[i + 1] > 0.0f || mask.rgba[i + 2] > 0.0f ? 1.0f : 0.0f;
    for (size_t c = 0; c < 4; ++c) mask.rgba[i + c] = keep;
  }
  mask = BoxShrink(mask, shrink);
  for (float& v : mask.rgba) v = v >= 1.0f - 1e-4f ? 1.0f : 0.0f;
  return mask;
}

}  // namespace vkr
