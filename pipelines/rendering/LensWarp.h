#pragma once
// Images through a lens (engine/scene/LensDistortion.h), both ways, on the host:
//  * a photograph taken through a lens is resampled once, when it is loaded, to the pinhole
//    image of the same K and size, which is all the likelihoods ever see (why there and not
//    per texel in the passes: docs/guide/REAL_CAMERAS.md); the pixels whose distorted position falls
//    outside the photograph are marked invalid, never compared as black;
//  * `synth` and `render` draw a distorted camera as an over-size, over-sampled pinhole view
//    that covers its whole distorted frame, resampled to the distorted image.
// Pixel coordinates follow COLMAP: the image spans [0,W]×[0,H], pixel (i, j) is centred at
// (i+0.5, j+0.5); a pinhole pixel p sees the normalised point K⁻¹p, a lens shows it at the
// pixel K·D(K⁻¹p).

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "engine/image/Image.h"
#include "engine/scene/Scene.h"

namespace vkr {

struct UndistortedPhoto {
  Image image;     // the pinhole image of K, bilinear from the photograph
  Image validity;  // 1 (all four channels) where the pixel may be compared, else 0
};

// The pinhole image of `photo`, taken through `lens` with intrinsics K. A pixel is valid
// when its distorted position lies inside the photograph ([0,W]×[0,H]) on the lens map's
// principal branch (undistorting it returns the same ray, which rules out the ghosts beyond
// a fold of strong distortion), and, with a `mask` (photograph-sized, 0 = ignore; any of its
// channels nonzero counts), when every mask pixel its bilinear sample touches is nonzero.
// Invalid pixels hold the clamped edge of the photograph, which keeps gradients near the
// border small (their values are never compared). Without a lens the image is `photo` itself.
UndistortedPhoto UndistortPhotograph(const Image& photo, const Image* mask, const Eigen::Matrix3d& K,
                                     const LensDistortion& lens);

// Where the pixels of a distorted camera's image come from in a pinhole view.
struct PinholeCover {
  // The camera's pose and K, without lens, shifted and enlarged to cover every ray of the
  // distorted frame (plus a margin for bilinear taps) and `oversample` times denser.
  Camera pinhole;
  // Per pixel of the distorted image (row-major), its position in `pinhole`'s image; NaN
  // where the lens has no ray for it (undistortion did not converge).
  std::vector<Eigen::Vector2d> source;
};

// Throws InputError naming the camera when its lens would need a pinhole view more than 8
// times its own size (a lens map that folds inside the frame).
PinholeCover CoverDistortedFrame(const Camera& camera, double oversample);

enum class LensResampling {
  Bilinear,      // colours
  Conservative,  // masks: the minimum of the four bilinear taps, so a masked pixel never shrinks away
};

// The distorted image (camera width × height) of a view rendered with `cover.pinhole`;
// pixels without a ray are 0.
Image ResampleThroughLens(const Image& pinhole_view, const PinholeCover& cover, int width, int height,
                          LensResampling resampling);

// render(camera) for a pinhole camera; for a camera with a lens, render(cover.pinhole)
// resampled to the distorted image (2× over-sampling keeps the bilinear resampling's blur
// below a quarter of a photograph pixel).
Image RenderThroughLens(const Camera& camera, const std::function<Image(const Camera&)>& render,
                        LensResampling resampling = LensResampling::Bilinear, double oversample = 2.0);

}  // namespace vkr
