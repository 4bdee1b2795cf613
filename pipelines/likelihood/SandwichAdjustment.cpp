#include "pipelines/likelihood/SandwichAdjustment.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace vkr {
namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

int Side(const std::vector<double>& m) {
  const int d = int(std::lround(std::sqrt(double(m.size()))));
  return size_t(d) * d == m.size() ? d : 0;
}

Eigen::MatrixXd Symmetric(const std::vector<double>& m, int d) {
  const Eigen::MatrixXd a = Eigen::Map<const RowMajor>(m.data(), d, d);
  return 0.5 * (a + a.transpose());
}

std::vector<double> Flat(const Eigen::MatrixXd& m) {
  std::vector<double> out(size_t(m.size()));
  Eigen::Map<RowMajor>(out.data(), m.rows(), m.cols()) = m;
  return out;
}

}  // namespace

std::vector<double> AdjustedCurvature(const std::vector<double>& inverse_h, const std::vector<double>& j) {
  const int d = Side(inverse_h);
  if (d == 0 || j.size() != inverse_h.size()) return {};
  const Eigen::LLT<Eigen::MatrixXd> inverse_llt(Symmetric(inverse_h, d));
  if (inverse_llt.info() != Eigen::Success) return {};
  const Eigen::MatrixXd h = inverse_llt.solve(Eigen::MatrixXd::Identity(d, d));
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (h + h.transpose()));
  if (llt.info() != Eigen::Success) return {};
  const Eigen::MatrixXd lower = llt.matrixL();
  // W = L⁻¹ J L⁻ᵀ (H = L Lᵀ): symmetric, with the eigenvalues of H⁻¹J; A = L W⁻¹ Lᵀ.
  const Eigen::MatrixXd half = lower.triangularView<Eigen::Lower>().solve(Symmetric(j, d));
  Eigen::MatrixXd w = lower.triangularView<Eigen::Lower>().solve(half.transpose());
  w = 0.5 * (w + w.transpose()).eval();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(w);
  if (eigen.info() != Eigen::Success || !eigen.eigenvalues().allFinite()) return {};
  Eigen::VectorXd inverse(d);
  for (int i = 0; i < d; ++i) inverse[i] = 1.0 / std::max(eigen.eigenvalues()[i], 1.0);
  const Eigen::MatrixXd v = lower * eigen.eigenvectors();
  const Eigen::MatrixXd a = v * inverse.asDiagonal() * v.transpose();
  return a.allFinite() ? Flat(a) : std::vector<double>{};
}

double CurvatureRatio(const std::vector<double>& adjusted, const std::vector<double>& raw,
                      const std::vector<double>& centre, const std::vector<double>& psi) {
  const size_t d = centre.size();
  double num = 0.0, den = 0.0;
  for (size_t i = 0; i < d; ++i)
    for (size_t k = 0; k < d; ++k) {
      const double dd = (psi[i] - centre[i]) * (psi[k] - centre[k]);
      num += adjusted[i * d + k] * dd;
      den += raw[i * d + k] * dd;
    }
  return den > 0.0 && num > 0.0 ? num / den : 1.0;
}

std::vector<double> RawInverseCurvature(const std::vector<double>& covariance, const std::vector<double>& adjusted,
                                        const std::vector<double>& raw) {
  const int d = Side(covariance);
  if (d == 0 || adjusted.size() != covariance.size() || raw.size() != covariance.size()) return {};
  const Eigen::LLT<Eigen::MatrixXd> raw_llt(Symmetric(raw, d));
  if (raw_llt.info() != Eigen::Success) return {};
  const Eigen::MatrixXd x = Symmetric(covariance, d) * Symmetric(adjusted, d) *
                            raw_llt.solve(Eigen::MatrixXd::Identity(d, d));
  return Flat(0.5 * (x + x.transpose()));
}

}  // namespace vkr
