// Photographs through a lens (pipelines/rendering/LensWarp.h): undistorted once on load, they equal
// the pinhole render of the same K away from the border, the border that falls outside the
// photograph is marked invalid, and the surface likelihood on distorted photographs read
// through a COLMAP OPENCV model peaks at the truth like the one on pinhole photographs.

#include <gtest/gtest.h>

#include <cmath>

#include "pipelines/likelihood/ReferenceImages.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"
#include "tests/common/GpuTest.h"
#include "tests/pipelines/RealCameraScenes.h"

namespace vkr::test {
namespace {

// Mean |difference| over the colour channels of the pixels of `a` and `b` at least `margin`
// pixels from the image edge and from any pixel `validity` marks invalid (all valid when
// `validity` is empty). `used` receives their number.
double MeanAbsDifference(const Image& a, const Image& b, const Image& validity, int margin, int* used) {
  double sum = 0.0;
  *used = 0;
  for (int y = margin; y < a.height - margin; ++y)
    for (int x = margin; x < a.width - margin; ++x) {
      bool ok = true;
      for (int dy = -margin; dy <= margin && ok && !validity.Empty(); ++dy)
        for (int dx = -margin; dx <= margin && ok; ++dx) ok = validity.At(x + dx, y + dy)[0] > 0.5f;
      if (!ok) continue;
      ++*used;
      for (int c = 0; c < 3; ++c) sum += std::abs(a.At(x, y)[c] - b.At(x, y)[c]) / 3.0;
    }
  return *used ? sum / *used : 0.0;
}

class LensPhotographs : public GpuTest {};

TEST_F(LensPhotographs, UndistortedPhotographEqualsThePinholeRenderWithItsBorderInvalid) {
  TempDir pinhole_dir;
  std::vector<double> truth;
  const Scene pinhole = ShootBox(device(), {}, pinhole_dir, false, &truth);
  for (const LensDistortion& lens : {BarrelLens(), PincushionLens()}) {
    SCOPED_TRACE(lens.Coefficient("k1") < 0 ? "barrel" : "pincushion");
    TempDir dir;
    const Scene scene = ShootBox(device(), {lens}, dir, false, &truth);
    const std::vector<Camera> cameras = scene.Cameras(truth);
    int invalid_total = 0;
    for (size_t c = 0; c < cameras.size(); ++c) {
      SCOPED_TRACE(cameras[c].name);
      ASSERT_EQ(cameras[c].distortion.model, DistortionModel::OpenCV) << "read through the COLMAP model";
      const CameraPhoto photo = LoadCameraPhoto(scene, int(c), 1);
      const Image reference = LoadImage(pinhole.cameras[c].image);
      // A barrel lens fills the frame: no validity to check. A pincushion lens leaves a border.
      EXPECT_EQ(photo.validity.Empty(), lens.Coefficient("k1") < 0);
      // The border: invalid exactly where the lens puts the pixel outside the photograph.
      const Camera& cam = cameras[c];
      int mismatches = 0;
      for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
          const Eigen::Vector3d ray = cam.K.inverse() * Eigen::Vector3d(x + 0.5, y + 0.5, 1);
          const Eigen::Vector2d p = (cam.K * cam.distortion.Distort(ray.head<2>()).homogeneous()).head<2>();
          const bool inside = p.x() >= 0 && p.x() <= cam.width && p.y() >= 0 && p.y() <= cam.height;
          mismatches += inside != (photo.validity.Empty() || photo.validity.At(x, y)[0] > 0.5f);
          invalid_total += !inside;
        }
      EXPECT_EQ(mismatches, 0);
      // Away from the border, the undistorted photograph is the pinhole render up to two
      // bilinear resamplings (synth's through the lens, the loader's back): ~1/255 on
      // average. The photograph as it came through the lens is far further off (≥ 2.8× for
      // the mild pincushion, ≥ 3.5× for the barrel).
      int used = 0, used_raw = 0;
      const double undistorted = MeanAbsDifference(photo.image, reference, photo.validity, 2, &used);
      const double raw = MeanAbsDifference(LoadImage(scene.cameras[c].image), reference, photo.validity, 2, &used_raw);
      EXPECT_GT(used, cam.width * cam.height / 2);
      EXPECT_LT(undistorted, 2.0 / 255.0);
      EXPECT_GT(raw, 2.0 * undistorted);
    }
    if (lens.Coefficient("k1") > 0) EXPECT_GT(invalid_total, 1000) << "a pincushion lens leaves a border";
  }
}

// Every parameter's profile (the others at the truth, 41 steps over its prior) peaks
// within one step of the truth on distorted photographs read through the COLMAP OPENCV
// model, and at the same step as on pinhole photographs, up to one.
TEST_F(LensPhotographs, SurfaceProfilesThroughColmapPeakAtTheTruth) {
  TempDir lens_dir, pinhole_dir;
  std::vector<double> truth;
  const Scene lens = ShootBox(device(), {BarrelLens()}, lens_dir, false, &truth);
  const Scene pinhole = ShootBox(device(), {}, pinhole_dir, false, &truth);
  constexpr int kSteps = 41;
  auto peaks = [&](const Scene& scene) {
    SurfaceLikelihoodOptions options = SurfaceLikelihoodOptions::FromScene(scene);
    options.atlas = 128;
    options.levels = 1;
    options.max_batch = kSteps;
    options.model.sigma = 4.0;
    SurfaceLikelihood likelihood(device(), scene, options);
    std::vector<int> out;
    for (size_t p = 0; p < scene.parameters.size(); ++p) {
      const Prior& prior = scene.parameters[p].prior;
      std::vector<std::vector<double>> batch(kSteps, truth);
      for (int k = 0; k < kSteps; ++k) batch[k][p] = prior.a + k * (prior.b - prior.a) / (kSteps - 1);
      const std::vector<Evaluation> e = likelihood.Evaluate(batch);
      int best = 0;
      for (int k = 1; k < kSteps; ++k)
        if (e[k].total() > e[best].total()) best = k;
      out.push_back(best);
    }
    return out;
  };
  const std::vector<int> through_lens = peaks(lens), without_lens = peaks(pinhole);
  for (size_t p = 0; p < truth.size(); ++p) {
    const Prior& prior = lens.parameters[p].prior;
    const double step = (prior.b - prior.a) / (kSteps - 1);
    const double truth_step = (truth[p] - prior.a) / step;
    EXPECT_LE(std::abs(through_lens[p] - truth_step), 1.0001) << lens.parameters[p].name;
    EXPECT_LE(std::abs(through_lens[p] - without_lens[p]), 1) << lens.parameters[p].name;
  }
}

}  // namespace
}  // namespace vkr::test
