#include "pipelines/ReferenceImages.h"

#include <algorithm>
#include <cmath>

#include "engine/common/InputError.h"
#include "engine/image/Pyramid.h"

namespace vkr {
namespace {

// The pyramid down to a few pixels, each level cropped to Vulkan's mip size max(1, n >> m)
// (the pyramid rounds up; a partial last row or column of a level is dropped).
std::vector<std::vector<uint8_t>> ReferenceMips(const Image& image) {
  int count = 1;
  while ((std::min(image.width, image.height) >> count) >= 4) ++count;
  std::vector<std::vector<uint8_t>> mips;
  for (Image& level : BuildPyramid(image, count)) {
    StoreGradientInAlpha(level);  // the noise model's |∇I|, free to sample with the colour
    const int m = int(mips.size());
    const int w = std::max(1, image.width >> m), h = std::max(1, image.height >> m);
    std::vector<uint8_t> bytes(size_t(w) * h * 4);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 4; ++c)
          bytes[(size_t(y) * w + x) * 4 + c] =
              uint8_t(std::lround(std::clamp(level.At(x, y)[c], 0.0f, 1.0f) * 255.0f));
    mips.push_back(std::move(bytes));
  }
  return mips;
}

}  // namespace

Image LoadCameraImage(const Scene& scene, int index, int levels) {
  const CameraModel& cam = scene.cameras.at(size_t(index));
  const std::string field = "cameras[" + std::to_string(index) + "].image";
  Image image = LoadImage(cam.image);
  if (image.width != cam.width || image.height != cam.height)
    throw InputError(scene.file.string(), field,
                     cam.image.string() + " is " + std::to_string(image.width) + "×" +
                         std::to_string(image.height) + " but the camera says " + std::to_string(cam.width) +
                         "×" + std::to_string(cam.height));
  if ((std::min(image.width, image.height) >> (levels - 1)) < 4)
    throw InputError(scene.file.string(), field,
                     cam.image.string() + " is too small for " + std::to_string(levels) + " pyramid levels");
  return image;
}

vk::GpuImage UploadReference(vk::Device& device, vk::Transfer& transfer, const Image& image) {
  const std::vector<std::vector<uint8_t>> mips = ReferenceMips(image);
  vk::GpuImageInfo info{uint32_t(image.width), uint32_t(image.height), 1, VK_FORMAT_R8G8B8A8_UNORM,
                        VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT};
  info.mip_levels = uint32_t(mips.size());
  vk::GpuImage reference(device, info);
  std::vector<const void*> data;
  for (const auto& mip : mips) data.push_back(mip.data());
  transfer.UploadMipChain(reference, data, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  return reference;
}

}  // namespace vkr
