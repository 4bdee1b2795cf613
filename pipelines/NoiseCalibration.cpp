#include "pipelines/NoiseCalibration.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

namespace vkr {
namespace {

const Image* FindImage(const LikelihoodDump& dump, const std::string& name) {
  for (const DumpImage& d : dump.images)
    if (d.name == name) return &d.image;
  return nullptr;
}

}  // namespace

nlohmann::json ToJson(const NoiseCalibration& c) {
  return {{"sigma", c.sigma},         {"sigma_estimated", c.sigma_estimated}, {"kappa", c.kappa},
          {"kappa_min", c.kappa_min}, {"kappa_max", c.kappa_max},             {"blocks", c.blocks},
          {"chi2_per_dof", c.chi2_per_dof}};
}

NoiseCalibration NoiseCalibrationFromJson(const nlohmann::json& j) {
  try {
    NoiseCalibration c;
    c.sigma = j.at("sigma").get<double>();
    c.sigma_estimated = j.at("sigma_estimated").get<bool>();
    c.kappa = j.at("kappa").get<double>();
    c.kappa_min = j.at("kappa_min").get<double>();
    c.kappa_max = j.at("kappa_max").get<double>();
    c.blocks = j.at("blocks").get<int>();
    c.chi2_per_dof = j.at("chi2_per_dof").get<double>();
    if (!(c.sigma > 0.0) || !(c.kappa > 0.0)) throw std::invalid_argument("sigma or kappa out of range");
    return c;
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(std::string("noise calibration: ") + e.what());
  }
}

namespace {

constexpr int kBlock = 8;  // texels per side of a sandwich block

// Per texel, its term of the log-likelihood, −½ (s_t/σ² − d_t), from a dump's deviation
// image (r = s_t/σ² capped, g = d_t); empty without one.
std::vector<double> TexelLogLikelihood(const LikelihoodDump& dump, bool chi2_correction, int* width) {
  const Image* deviation = FindImage(dump, "deviation");
  if (!deviation) return {};
  *width = deviation->width;
  std::vector<double> out(size_t(deviation->width) * deviation->height);
  for (int y = 0; y < deviation->height; ++y)
    for (int x = 0; x < deviation->width; ++x) {
      const float* d = deviation->At(x, y);
      out[size_t(y) * deviation->width + x] = -0.5 * (double(d[0]) - (chi2_correction ? double(d[1]) : 0.0));
    }
  return out;
}

// κ = tr(H⁻¹J)/d and the eigenvalue range of H⁻¹J (NoiseCalibration.h).
void SandwichFactor(Likelihood& likelihood, const std::vector<double>& psi, const Eigen::MatrixXd& inverse_h,
                    NoiseCalibration* c) {
  const int d = int(psi.size());
  const bool correction = likelihood.model().chi2_correction;
  std::vector<std::vector<double>> gradient(static_cast<size_t>(d));  // per parameter, per texel
  int width = 0;
  for (int i = 0; i < d; ++i) {
    const double h = std::sqrt(std::max(inverse_h(i, i), 0.0));
    if (!(h > 0.0) || !std::isfinite(h)) return;
    std::vector<double> plus = psi, minus = psi;
    plus[size_t(i)] += h;
    minus[size_t(i)] -= h;
    const std::vector<double> up = TexelLogLikelihood(likelihood.EvaluateAndDump(plus, nullptr), correction, &width);
    const std::vector<double> down = TexelLogLikelihood(likelihood.EvaluateAndDump(minus, nullptr), correction, &width);
    if (up.empty() || up.size() != down.size()) return;
    gradient[size_t(i)].resize(up.size());
    for (size_t t = 0; t < up.size(); ++t) gradient[size_t(i)][t] = (up[t] - down[t]) / (2.0 * h);
  }
  const int height = int(gradient[0].size()) / width;
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(d, d);
  int blocks = 0;
  for (int by = 0; by < height; by += kBlock)
    for (int bx = 0; bx < width; bx += kBlock) {
      Eigen::VectorXd g = Eigen::VectorXd::Zero(d);
      for (int y = by; y < std::min(height, by + kBlock); ++y)
        for (int x = bx; x < std::min(width, bx + kBlock); ++x)
          for (int i = 0; i < d; ++i) g[i] += gradient[size_t(i)][size_t(y) * width + x];
      if (g.squaredNorm() == 0.0) continue;
      j += g * g.transpose();
      ++blocks;
    }
  c->blocks = blocks;
  if (blocks < 2 * d) return;  // too few to estimate J: keep κ = 1
  const Eigen::MatrixXd m = inverse_h * j;
  const Eigen::VectorXcd eigen = m.eigenvalues();
  c->kappa = std::clamp(m.trace() / double(d), 1e-3, 1e6);
  c->kappa_min = eigen.real().minCoeff();
  c->kappa_max = eigen.real().maxCoeff();
}

}  // namespace

NoiseCalibration CalibrateNoise(Likelihood& likelihood, const std::vector<double>& psi,
                                const std::vector<double>& covariance, double current_kappa,
                                bool estimate_sigma, double sigma_floor) {
  const int level = likelihood.level();
  likelihood.SetLevel(0);
  NoiseCalibration c;
  const double sigma_before = likelihood.model().sigma;
  c.sigma = sigma_before;
  c.sigma_estimated = estimate_sigma;
  if (estimate_sigma) {
    // σ² ← S/N: S is capped at 9 dof·σ² per texel, so the cap moves with σ; a few rounds
    // settle it (the capped texels are the few outliers).
    for (int round = 0; round < 4; ++round) {
      const Evaluation e = likelihood.Evaluate({psi})[0];
      if (!(e.scalars.dof > 0.0)) break;
      const double next = std::max(255.0 * std::sqrt(e.scalars.sum_squares / e.scalars.dof), sigma_floor);
      const bool settled = std::abs(next - c.sigma) < 1e-3 * c.sigma;
      c.sigma = next;
      likelihood.SetSigma(c.sigma);
      if (settled) break;
    }
  }
  c.chi2_per_dof = Chi2PerDof(likelihood.Evaluate({psi})[0].scalars, c.sigma);
  const size_t d = psi.size();
  if (covariance.size() == d * d && d > 0) {
    // The curvature of the raw log-likelihood at the new σ: undo κ, and the S term scales
    // with 1/σ² (the N term has no curvature).
    Eigen::MatrixXd inverse_h(d, d);
    for (size_t i = 0; i < d; ++i)
      for (size_t k = 0; k < d; ++k) inverse_h(Eigen::Index(i), Eigen::Index(k)) = covariance[i * d + k];
    inverse_h *= (c.sigma * c.sigma) / (sigma_before * sigma_before) / current_kappa;
    SandwichFactor(likelihood, psi, inverse_h, &c);
  }
  likelihood.SetLevel(level);
  return c;
}

}  // namespace vkr
