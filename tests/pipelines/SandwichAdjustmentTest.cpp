// The sandwich's curvature adjustment (SandwichAdjustment.h): the adjusted target's curvature
// at the mode must be H J⁻¹ H, never narrower than H in any direction, the magnitude
// adjustment's where J is a multiple of H, and a checkpoint must carry it.
#include <cmath>
#include <stdexcept>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "pipelines/likelihood/NoiseCalibration.h"
#include "pipelines/likelihood/SandwichAdjustment.h"

namespace vkr {
namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

std::vector<double> Flat(const Eigen::MatrixXd& m) {
  std::vector<double> out(size_t(m.size()));
  Eigen::Map<RowMajor>(out.data(), m.rows(), m.cols()) = m;
  return out;
}

Eigen::MatrixXd Square(const std::vector<double>& m, int d) { return Eigen::Map<const RowMajor>(m.data(), d, d); }

// A correlated curvature, as the photographs' parameters have.
Eigen::MatrixXd Curvature() {
  Eigen::MatrixXd h(3, 3);
  h << 40.0, 12.0, -5.0, 12.0, 9.0, 1.5, -5.0, 1.5, 4.0;
  return h;
}

// J with H⁻¹J's eigenvalues far apart (3.8 … 109 on house): one direction widens much more.
Eigen::MatrixXd SpreadSandwich(const Eigen::MatrixXd& h) {
  Eigen::MatrixXd j = h + 80.0 * h.col(0) * h.col(0).transpose() / h(0, 0);
  return 3.0 * j;
}

TEST(SandwichAdjustment, TheAdjustedCurvatureIsTheSandwichs) {
  const Eigen::MatrixXd h = Curvature(), j = SpreadSandwich(h);
  const std::vector<double> a = AdjustedCurvature(Flat(h.inverse()), Flat(j));
  ASSERT_EQ(a.size(), 9u);
  const Eigen::MatrixXd expected = h * j.inverse() * h;
  EXPECT_LT((Square(a, 3) - expected).norm(), 1e-9 * expected.norm());
}

TEST(SandwichAdjustment, AMultipleOfTheCurvatureIsTheMagnitudeAdjustment) {
  const Eigen::MatrixXd h = Curvature();
  const std::vector<double> a = AdjustedCurvature(Flat(h.inverse()), Flat(25.0 * h));
  ASSERT_EQ(a.size(), 9u);
  EXPECT_LT((Square(a, 3) - h / 25.0).norm(), 1e-9 * h.norm());
}

TEST(SandwichAdjustment, NoDirectionBecomesNarrowerThanTheRawLikelihood) {
  const Eigen::MatrixXd h = Curvature();
  // J smaller than H in every direction: H⁻¹J's eigenvalues are below 1, floored there.
  const std::vector<double> a = AdjustedCurvature(Flat(h.inverse()), Flat(0.2 * h));
  ASSERT_EQ(a.size(), 9u);
  EXPECT_LT((Square(a, 3) - h).norm(), 1e-9 * h.norm());
}

TEST(SandwichAdjustment, ACurvatureThatIsNotAMaximumsGivesNone) {
  Eigen::MatrixXd h = Curvature();
  h(2, 2) = -4.0;
  EXPECT_TRUE(AdjustedCurvature(Flat(h), Flat(Curvature())).empty());
  EXPECT_TRUE(AdjustedCurvature({1.0, 0.0, 0.0}, {1.0, 0.0, 0.0}).empty());  // not square
}

// ℓ_adj(ψ) = r(δ) ℓ(ψ) for a quadratic ℓ(ψ) = −½δᵀHδ: its curvature at the mode, by central
// differences, is A; the covariance measured there converts back to H⁻¹.
TEST(SandwichAdjustment, TheVerticalTargetHasTheAdjustedCurvatureAtTheMode) {
  const Eigen::MatrixXd h = Curvature(), j = SpreadSandwich(h);
  const std::vector<double> a = AdjustedCurvature(Flat(h.inverse()), Flat(j)), raw = Flat(h);
  const std::vector<double> centre = {0.3, -1.0, 2.0};
  const auto target = [&](const Eigen::Vector3d& delta) {
    std::vector<double> psi = centre;
    for (int i = 0; i < 3; ++i) psi[size_t(i)] += delta[i];
    return CurvatureRatio(a, raw, centre, psi) * (-0.5 * delta.dot(h * delta));
  };
  const double step = 1e-3;
  Eigen::Matrix3d measured;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d ei = step * Eigen::Vector3d::Unit(i), ek = step * Eigen::Vector3d::Unit(k);
      measured(i, k) = -(target(ei + ek) - target(ei - ek) - target(ek - ei) + target(-ei - ek)) / (4 * step * step);
    }
  EXPECT_LT((measured - Square(a, 3)).norm(), 1e-6 * Square(a, 3).norm()) << measured << "\n\n" << Square(a, 3);
  const std::vector<double> back = RawInverseCurvature(Flat(measured.inverse()), a, raw);
  ASSERT_EQ(back.size(), 9u);
  EXPECT_LT((Square(back, 3) - h.inverse()).norm(), 1e-5 * h.inverse().norm());
  // A new σ scales every direction's curvature alike; the conversion follows it.
  const std::vector<double> scaled = RawInverseCurvature(Flat(2.0 * measured.inverse()), a, raw);
  EXPECT_LT((Square(scaled, 3) - 2.0 * h.inverse()).norm(), 1e-5 * h.inverse().norm());
}

TEST(SandwichAdjustment, TheRatioLiesBetweenTheSandwichsExtremes) {
  const Eigen::MatrixXd h = Curvature(), j = SpreadSandwich(h);
  const std::vector<double> a = AdjustedCurvature(Flat(h.inverse()), Flat(j));
  const Eigen::VectorXcd eigen = (h.inverse() * j).eigenvalues();
  const double lo = 1.0 / eigen.real().maxCoeff(), hi = 1.0 / std::max(eigen.real().minCoeff(), 1.0);
  for (const std::vector<double>& psi : {std::vector<double>{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, -2, 0.5}}) {
    const double r = CurvatureRatio(a, Flat(h), {0, 0, 0}, psi);
    EXPECT_GE(r, lo * (1 - 1e-9));
    EXPECT_LE(r, hi * (1 + 1e-9));
  }
  EXPECT_EQ(CurvatureRatio(a, Flat(h), {0, 0, 0}, {0, 0, 0}), 1.0);  // at the centre
}

// A checkpoint carries the adjustment, so a resumed run evaluates the same target.
TEST(SandwichAdjustment, ACalibrationsJsonCarriesIt) {
  NoiseCalibration c;
  c.kappa = 12.5;
  c.adjusted_curvature = {0.5, 0.1, 0.1, 0.25};
  c.raw_curvature = {5.0, 1.0, 1.0, 2.5};
  c.adjustment_centre = {1.0, -2.0};
  c.centre_total = 1234.5;
  const NoiseCalibration back = NoiseCalibrationFromJson(ToJson(c));
  EXPECT_EQ(back.adjusted_curvature, c.adjusted_curvature);
  EXPECT_EQ(back.raw_curvature, c.raw_curvature);
  EXPECT_EQ(back.adjustment_centre, c.adjustment_centre);
  EXPECT_EQ(back.centre_total, c.centre_total);
  EXPECT_FALSE(NoiseCalibrationFromJson(ToJson(NoiseCalibration{})).CurvatureAdjusted());
  nlohmann::json bad = ToJson(c);
  bad["curvature_adjustment"]["raw"] = {0.5, 0.1, 0.1};
  EXPECT_THROW(NoiseCalibrationFromJson(bad), std::invalid_argument);
}

}  // namespace
}  // namespace vkr
