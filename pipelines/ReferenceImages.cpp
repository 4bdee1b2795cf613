#include "pipelines/ReferenceImages.h"

#include <algorithm>
#include <cmath>

#include "engine/common/InputError.h"
#include "engine/image/Pyramid.h"
#include "pipelines/LensWarp.h"

namespace vkr {
namespace {

// Mip levels of a reference: the pyramid down to a smallest side of 4 pixels.
int ReferenceMipCount(const Image& image) {
  int count = 1;
  while ((std::min(image.width, image.height) >> count) >= 4) ++count;
  return count;
}

// Channels [0, channels) of a pyramid, each level cropped to Vulkan's mip size
// max(1, n >> m) (the pyramid rounds up; a partial last row or column of a level is
// dropped), as 8-bit values.
std::vector<std::vector<uint8_t>> PackMips(const std::vector<Image>& levels, int channels) {
  std::vector<std::vector<uint8_t>> mips;
  const int width = levels.front().width, height = levels.front().height;
  for (const Image& level : levels) {
    const int m = int(mips.size());
    const int w = std::max(1, width >> m), h = std::max(1, height >> m);
    std::vector<uint8_t> bytes(size_t(w) * h * channels);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < channels; ++c)
          bytes[(size_t(y) * w + x) * channels + c] =
              uint8_t(std::lround(std::clamp(level.At(x, y)[c], 0.0f, 1.0f) * 255.0f));
    mips.push_back(std::move(bytes));
  }
  return mips;
}

vk::GpuImage UploadMips(vk::Device& device, vk::Transfer& transfer, const std::vector<std::vector<uint8_t>>& mips,
                        int width, int height, VkFormat format) {
  vk::GpuImageInfo info{uint32_t(width), uint32_t(height), 1, format,
                        VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT};
  info.mip_levels = uint32_t(mips.size());
  vk::GpuImage image(device, info);
  std::vector<const void*> data;
  for (const auto& mip : mips) data.push_back(mip.data());
  transfer.UploadMipChain(image, data, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  return image;
}

std::string Size(int w, int h) { return std::to_string(w) + "×" + std::to_string(h); }

}  // namespace

CameraPhoto LoadCameraPhoto(const Scene& scene, int index, int levels) {
  const CameraModel& cam = scene.cameras.at(size_t(index));
  const std::string field = "cameras[" + std::to_string(index) + "].image";
  Image image = LoadImage(cam.image);
  if (image.width != cam.width || image.height != cam.height)
    throw InputError(scene.file.string(), field,
                     cam.image.string() + " is " + Size(image.width, image.height) + " but the camera says " +
                         Size(cam.width, cam.height));
  if ((std::min(image.width, image.height) >> (levels - 1)) < 4)
    throw InputError(scene.file.string(), field,
                     cam.image.string() + " is too small for " + std::to_string(levels) + " pyramid levels");
  Image mask;
  if (!cam.mask.empty()) {
    mask = LoadImage(cam.mask);  // the loader checked it; it may have changed since
    if (mask.width != cam.width || mask.height != cam.height)
      throw InputError(scene.file.string(), "masks",
                       "mask " + cam.mask.string() + " is " + Size(mask.width, mask.height) + " but camera " +
                           cam.name + " is " + Size(cam.width, cam.height));
  }
  CameraPhoto photo;
  if (cam.distortion.IsNone() && mask.Empty()) {
    photo.image = std::move(image);
    return photo;
  }
  // A camera with a lens has a constant K (the loader makes sure): Ψ does not matter.
  const Eigen::Matrix3d K = scene.Cameras(scene.InitialValues()).at(size_t(index)).K;
  UndistortedPhoto undistorted = UndistortPhotograph(image, mask.Empty() ? nullptr : &mask, K, cam.distortion);
  photo.image = std::move(undistorted.image);
  photo.validity = std::move(undistorted.validity);
  return photo;
}

std::vector<Image> BuildValidityPyramid(const Image& validity, int levels) {
  std::vector<Image> pyramid = BuildPyramid(validity, levels);
  for (Image& level : pyramid) {
    // Binary: 1 only where the blur averaged nothing but valid pixels (the taps' weights
    // are multiples of 1/32, so an all-valid footprint sums to exactly 1 down to level 3
    // and to within a float's rounding below).
    Image binary(level.width, level.height);
    auto valid = [&](int x, int y) { return level.At(x, y)[0] >= 0.999f; };
    for (int y = 0; y < level.height; ++y)
      for (int x = 0; x < level.width; ++x) {
        const bool keep = valid(x, y) && valid(std::max(0, x - 1), y) && valid(std::min(level.width - 1, x + 1), y) &&
                          valid(x, std::max(0, y - 1)) && valid(x, std::min(level.height - 1, y + 1));
        float* out = binary.At(x, y);
        out[0] = out[1] = out[2] = out[3] = keep ? 1.0f : 0.0f;
      }
    level = std::move(binary);
  }
  return pyramid;
}

vk::GpuImage UploadReference(vk::Device& device, vk::Transfer& transfer, const Image& image) {
  std::vector<Image> levels = BuildPyramid(image, ReferenceMipCount(image));
  for (Image& level : levels) StoreGradientInAlpha(level);  // the noise model's |∇I|, free to sample with the colour
  return UploadMips(device, transfer, PackMips(levels, 4), image.width, image.height, VK_FORMAT_R8G8B8A8_UNORM);
}

vk::GpuImage UploadValidity(vk::Device& device, vk::Transfer& transfer, const CameraPhoto& photo) {
  return UploadValidity(device, transfer, photo.validity);
}

vk::GpuImage UploadValidity(vk::Device& device, vk::Transfer& transfer, const Image& validity) {
  if (validity.Empty()) {
    // Every pixel counts: a 1×1 white texture reads 1 at any uv and LOD.
    const std::vector<std::vector<uint8_t>> white{{255}};
    return UploadMips(device, transfer, white, 1, 1, VK_FORMAT_R8_UNORM);
  }
  // The validity has the photograph's size, so its mip count is the reference's.
  const std::vector<Image> levels = BuildValidityPyramid(validity, ReferenceMipCount(validity));
  return UploadMips(device, transfer, PackMips(levels, 1), validity.width, validity.height, VK_FORMAT_R8_UNORM);
}

}  // namespace vkr
