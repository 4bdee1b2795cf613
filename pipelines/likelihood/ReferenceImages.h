#pragma once
// A camera's photograph as both likelihoods sample it: loaded and checked against its
// camera, undistorted to the pinhole of its K when it has a lens (LensWarp.h), then uploaded
// as an RGBA8 mip chain (mip m = pyramid level m, Pyramid.h) whose alpha holds |∇I| for the
// noise model (Evaluation.h), next to an R8 mip chain of the same size saying which texels
// may be compared (the camera's mask times the lens's valid frame).

#include <vector>

#include "engine/image/Image.h"
#include "engine/scene/Scene.h"
#include "engine/vk/Commands.h"
#include "engine/vk/Resources.h"

namespace vkr {

struct CameraPhoto {
  Image image;     // the photograph, undistorted when the camera has a lens
  // 1 where a pixel may be compared, 0 where not (all four channels); empty when every pixel
  // may (no mask, and no lens or one that fills the frame), which costs nothing downstream.
  Image validity;
};

// Loads camera `index`'s photograph (undistorted) and its validity. Throws InputError (scene
// file, cameras[i].image / masks) when the image or mask size differs from the camera's, a
// mask cannot be read, or the image is too small for `levels` pyramid levels.
CameraPhoto LoadCameraPhoto(const Scene& scene, int index, int levels);

// The pyramid of a validity image (valid where its first channel is ≥ ½), binary at every
// level: level m is 1 where every base pixel that BuildPyramid's level-m pixel averages is
// valid, and so are those of its four neighbours (StoreGradientInAlpha's central
// differences read them). So a colour or gradient sampled only from valid texels of this
// pyramid depends on valid pixels alone, and a sample touching an invalid texel reads below
// 1: the likelihoods drop samples reading below 0.999 (view_texture.frag, image_warp.glsl).
// A texel weighing less than 1/1000 in a bilinear sample gets through that threshold; GPUs
// filter with 8-bit weights (lavapipe included), which round such a weight to 0.
std::vector<Image> BuildValidityPyramid(const Image& validity, int levels);

// The prefiltered reference texture of `image`, in SHADER_READ_ONLY_OPTIMAL.
vk::GpuImage UploadReference(vk::Device& device, vk::Transfer& transfer, const Image& image);

// The validity texture matching UploadReference(photo.image) mip for mip (R8, 0 or 1), in
// SHADER_READ_ONLY_OPTIMAL; none (an empty GpuImage, whose view() is VK_NULL_HANDLE) when
// photo.validity is empty: the passes then use pipelines that do not read it.
vk::GpuImage UploadValidity(vk::Device& device, vk::Transfer& transfer, const CameraPhoto& photo);
// The same from a validity image of the photograph's size (empty: every pixel counts).
vk::GpuImage UploadValidity(vk::Device& device, vk::Transfer& transfer, const Image& validity);

}  // namespace vkr
