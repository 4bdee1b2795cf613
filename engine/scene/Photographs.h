#pragma once
// A camera's photograph at the size the scene works at. A scene's `max_side`
// (docs/guide/SCENE_FORMAT.md) shrinks every larger photograph by an integer factor, so a
// 12-megapixel phone photograph goes in without resizing it by hand: each pixel the mean of
// the factor² it covers, the remainder at the right and bottom cropped, K scaled to match.

#include <filesystem>

#include "engine/image/Image.h"

namespace vkr {

// The smallest integer factor that brings width × height within max_side on its longer side
// (1 when max_side is 0, "none", or the image is already within it).
int ShrinkFactor(int width, int height, int max_side);

// The photograph in `file` shrunk by `shrink` (Pyramid.h, BoxShrink).
Image LoadPhotograph(const std::filesystem::path& file, int shrink);

// A validity mask (0 = ignore) shrunk by `shrink`: a pixel is valid only where every pixel it
// covers is, so what a mask hides never leaks into a mixed pixel.
Image LoadMask(const std::filesystem::path& file, int shrink);

}  // namespace vkr
