// Lens distortion (engine/scene/LensDistortion.h): the formula is OpenCV's and COLMAP's,
// its Jacobian is its derivative, and undistortion inverts it to far below a pixel's
// ten-thousandth over a whole image, for every model.

#include "engine/scene/LensDistortion.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/scene/SceneTestUtil.h"

namespace vkr::test {
namespace {

LensDistortion Lens(DistortionModel model, std::vector<double> coefficients) {
  LensDistortion d;
  d.model = model;
  for (size_t i = 0; i < coefficients.size(); ++i) d.coefficients[i] = coefficients[i];
  return d;
}

// One lens per model, strong enough to move the corners of a 640×480, f = 500 image by
// several pixels (the asset bar uses k1 = −0.12, k2 = 0.03).
std::vector<LensDistortion> EveryModel() {
  return {Lens(DistortionModel::SimpleRadial, {-0.2}),
          Lens(DistortionModel::Radial, {-0.25, 0.05}),
          Lens(DistortionModel::OpenCV, {-0.12, 0.03, 0.001, -0.0015}),
          Lens(DistortionModel::FullOpenCV, {-0.3, 0.1, 0.0005, 0.0007, -0.01, 0.05, 0.01, 0.001})};
}

TEST(LensDistortion, IsOpenCVsFormula) {
  // x_d = x·radial + 2 p1 x y + p2 (r² + 2x²), y_d = y·radial + p1 (r² + 2y²) + 2 p2 x y.
  const double x = 0.3, y = -0.2, r2 = x * x + y * y;
  const LensDistortion opencv = Lens(DistortionModel::OpenCV, {-0.12, 0.03, 0.001, -0.0015});
  const double radial = 1 - 0.12 * r2 + 0.03 * r2 * r2;
  const Eigen::Vector2d d = opencv.Distort({x, y});
  EXPECT_NEAR(d.x(), x * radial + 2 * 0.001 * x * y - 0.0015 * (r2 + 2 * x * x), 1e-15);
  EXPECT_NEAR(d.y(), y * radial + 0.001 * (r2 + 2 * y * y) + 2 * -0.0015 * x * y, 1e-15);

  const LensDistortion full = Lens(DistortionModel::FullOpenCV, {0.1, 0.2, 0, 0, 0.3, 0.4, 0.5, 0.6});
  const double rational = (1 + 0.1 * r2 + 0.2 * r2 * r2 + 0.3 * r2 * r2 * r2) /
                          (1 + 0.4 * r2 + 0.5 * r2 * r2 + 0.6 * r2 * r2 * r2);
  EXPECT_NEAR(full.Distort({x, y}).x(), x * rational, 1e-15);

  // SIMPLE_RADIAL's k and RADIAL's k1 k2 are OpenCV's k1 (k2).
  EXPECT_EQ(Lens(DistortionModel::SimpleRadial, {-0.2}).Distort({x, y}),
            Lens(DistortionModel::OpenCV, {-0.2, 0, 0, 0}).Distort({x, y}));
  EXPECT_EQ(Lens(DistortionModel::Radial, {-0.2, 0.1}).Distort({x, y}),
            Lens(DistortionModel::OpenCV, {-0.2, 0.1, 0, 0}).Distort({x, y}));
  EXPECT_EQ(LensDistortion{}.Distort({x, y}), Eigen::Vector2d(x, y));
}

TEST(LensDistortion, JacobianIsTheDerivative) {
  for (const LensDistortion& lens : EveryModel()) {
    SCOPED_TRACE(ToString(lens.model));
    for (const Eigen::Vector2d p : {Eigen::Vector2d(0.3, -0.2), Eigen::Vector2d(-0.6, 0.45), Eigen::Vector2d(0, 0)}) {
      Eigen::Matrix2d J;
      lens.Distort(p, &J);
      const double h = 1e-6;
      for (int k = 0; k < 2; ++k) {
        const Eigen::Vector2d e = Eigen::Vector2d::Unit(k) * h;
        const Eigen::Vector2d numeric = (lens.Distort(p + e) - lens.Distort(p - e)) / (2 * h);
        EXPECT_NEAR((J.col(k) - numeric).norm(), 0.0, 1e-8) << p.transpose();
      }
    }
  }
}

// Every pixel of a 640×480 image, f = 500: distorted pixel → undistort → distort, and
// undistorted pixel → distort → undistort, both back within 1e-4 px (in fact ~1e-9).
TEST(LensDistortion, UndistortInvertsDistortOverTheWholeImage) {
  const double f = 500, cx = 320, cy = 240;
  for (const LensDistortion& lens : EveryModel()) {
    SCOPED_TRACE(ToString(lens.model));
    double worst_from_distorted = 0, worst_from_undistorted = 0, largest_shift = 0;
    int failures = 0;
    for (int y = 0; y <= 480; ++y)
      for (int x = 0; x <= 640; ++x) {
        const Eigen::Vector2d n((x - cx) / f, (y - cy) / f);  // pixel corners: the frame's edge included
        Eigen::Vector2d u;
        if (!lens.Undistort(n, &u)) {
          ++failures;
          continue;
        }
        worst_from_distorted = std::max(worst_from_distorted, f * (lens.Distort(u) - n).norm());
        largest_shift = std::max(largest_shift, f * (u - n).norm());
        Eigen::Vector2d back;
        ASSERT_TRUE(lens.Undistort(lens.Distort(n), &back));
        worst_from_undistorted = std::max(worst_from_undistorted, f * (back - n).norm());
      }
    EXPECT_EQ(failures, 0);
    EXPECT_LT(worst_from_distorted, 1e-4);
    EXPECT_LT(worst_from_undistorted, 1e-4);
    EXPECT_GT(largest_shift, 5.0) << "the lens should move the corners by pixels";
  }
}

TEST(LensDistortion, NamesAndCoefficients) {
  DistortionModel m;
  EXPECT_TRUE(FromString("FULL_OPENCV", &m));
  EXPECT_EQ(m, DistortionModel::FullOpenCV);
  EXPECT_FALSE(FromString("OPENCV_FISHEYE", &m));
  EXPECT_FALSE(FromString("NONE", &m));
  EXPECT_EQ(CoefficientNames(DistortionModel::SimpleRadial), std::vector<std::string>{"k"});
  EXPECT_EQ(CoefficientNames(DistortionModel::FullOpenCV).size(), 8u);
  EXPECT_EQ(Lens(DistortionModel::OpenCV, {1, 2, 3, 4}).Coefficient("p1"), 3.0);
  EXPECT_THROW(Lens(DistortionModel::OpenCV, {1, 2, 3, 4}).Coefficient("k3"), std::invalid_argument);
}

TEST(LensDistortion, CommandLineSpec) {
  const LensDistortion d = ParseDistortionSpec("OPENCV:k1=-0.12,k2=0.03", "--distortion");
  EXPECT_EQ(d.model, DistortionModel::OpenCV);
  EXPECT_EQ(d.Coefficient("k1"), -0.12);
  EXPECT_EQ(d.Coefficient("k2"), 0.03);
  EXPECT_EQ(d.Coefficient("p1"), 0.0);
  EXPECT_EQ(ParseDistortionSpec("RADIAL", "--distortion").model, DistortionModel::Radial);
  EXPECT_TRUE(FailsWith([] { ParseDistortionSpec("FISHEYE:k1=1", "--distortion"); },
                        {"--distortion", "unknown distortion model 'FISHEYE'", "OPENCV, FULL_OPENCV"}));
  EXPECT_TRUE(FailsWith([] { ParseDistortionSpec("OPENCV:k3=1", "--distortion"); }, {"k1, k2, p1, p2"}));
  EXPECT_TRUE(FailsWith([] { ParseDistortionSpec("OPENCV:k1=1,k1=2", "--distortion"); }, {"k1 is given twice"}));
  EXPECT_TRUE(FailsWith([] { ParseDistortionSpec("OPENCV:k1=x", "--distortion"); }, {"not a finite number"}));
  EXPECT_TRUE(FailsWith([] { ParseDistortionSpec("OPENCV:k1=inf", "--distortion"); }, {"not a finite number"}));
}

}  // namespace
}  // namespace vkr::test
