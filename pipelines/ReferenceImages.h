#pragma once
// A camera's photograph as both likelihoods sample it: loaded and checked against its
// camera, then uploaded as an RGBA8 mip chain (mip m = pyramid level m, Pyramid.h) whose
// alpha holds |∇I| for the noise model (Evaluation.h).

#include "engine/scene/Scene.h"
#include "engine/vk/Commands.h"
#include "engine/vk/Resources.h"

namespace vkr {

// Loads camera `index`'s image. Throws InputError (scene file, cameras[i].image) when its size
// differs from the camera's or it is too small for `levels` pyramid levels.
Image LoadCameraImage(const Scene& scene, int index, int levels);

// The prefiltered reference texture of `image`, in SHADER_READ_ONLY_OPTIMAL.
vk::GpuImage UploadReference(vk::Device& device, vk::Transfer& transfer, const Image& image);

}  // namespace vkr
