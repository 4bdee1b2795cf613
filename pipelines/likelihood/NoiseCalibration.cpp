#include "pipelines/likelihood/NoiseCalibration.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "pipelines/likelihood/SandwichAdjustment.h"

namespace vkr {
namespace {

const Image* FindImage(const LikelihoodDump& dump, const std::string& name) {
  for (const DumpImage& d : dump.images)
    if (d.name == name) return &d.image;
  return nullptr;
}

}  // namespace

nlohmann::json ToJson(const NoiseCalibration& c) {
  nlohmann::json json = {
      {"sigma", c.sigma},   {"position_sd", c.position_sd}, {"sigma_estimated", c.sigma_estimated},
      {"kappa", c.kappa},   {"kappa_min", c.kappa_min},     {"kappa_max", c.kappa_max},
      {"blocks", c.blocks}, {"block", c.block},             {"chi2_per_dof", c.chi2_per_dof},
      {"photometric", c.photometric}, {"curvature_doubtful", c.CurvatureDoubtful()}};
  if (!c.noise_rings.empty()) json["noise_correlation"] = {{"kappa", c.kappa_noise}, {"rings", c.noise_rings}};
  if (c.CurvatureAdjusted())
    json["curvature_adjustment"] = {{"adjusted", c.adjusted_curvature}, {"raw", c.raw_curvature},
                                    {"centre", c.adjustment_centre},     {"centre_total", c.centre_total}};
  return json;
}

double KappaFromJson(const nlohmann::json& calibration) {
  if (!calibration.is_object()) return 1.0;
  const auto kappa = calibration.find("kappa");
  return kappa != calibration.end() && kappa->is_number() ? kappa->get<double>() : 1.0;
}

NoiseCalibration NoiseCalibrationFromJson(const nlohmann::json& j) {
  try {
    NoiseCalibration c;
    c.sigma = j.at("sigma").get<double>();
    c.position_sd = j.at("position_sd").get<double>();
    c.photometric = j.at("photometric");
    c.sigma_estimated = j.at("sigma_estimated").get<bool>();
    c.kappa = j.at("kappa").get<double>();
    c.kappa_min = j.at("kappa_min").get<double>();
    c.kappa_max = j.at("kappa_max").get<double>();
    // Counts as JSON integers: get<int> would cast a float, undefined beyond int's range.
    const auto count = [](const nlohmann::json& n, const char* name) {
      if (!n.is_number_integer() || n.get<int64_t>() < 0 || n.get<int64_t>() > (int64_t(1) << 30))
        throw std::invalid_argument(std::string(name) + " is not a count: " + n.dump());
      return int(n.get<int64_t>());
    };
    c.blocks = count(j.at("blocks"), "blocks");
    // Checkpoints written before the block size was chosen have none: 8.
    c.block = j.contains("block") ? count(j.at("block"), "block") : 8;
    c.chi2_per_dof = j.at("chi2_per_dof").get<double>();
    // Calibrations written before κ was measured from the residuals have none: 1.
    if (const auto n = j.find("noise_correlation"); n != j.end()) {
      c.kappa_noise = n->at("kappa").get<double>();
      c.noise_rings = n->at("rings").get<std::vector<double>>();
      if (!(c.kappa_noise >= 1.0)) throw std::invalid_argument("noise_correlation's kappa is below 1");
    }
    if (const auto a = j.find("curvature_adjustment"); a != j.end()) {
      c.adjusted_curvature = a->at("adjusted").get<std::vector<double>>();
      c.raw_curvature = a->at("raw").get<std::vector<double>>();
      c.adjustment_centre = a->at("centre").get<std::vector<double>>();
      c.centre_total = a->at("centre_total").get<double>();
      const size_t d = c.adjustment_centre.size();
      if (d == 0 || c.adjusted_curvature.size() != d * d || c.raw_curvature.size() != d * d)
        throw std::invalid_argument("curvature_adjustment's matrices are not d × d for its centre of " +
                                    std::to_string(d));
    }
    if (!(c.sigma > 0.0) || !(c.kappa > 0.0) || !(c.position_sd >= 0.0))
      throw std::invalid_argument("sigma, position_sd or kappa out of range");
    return c;
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(std::string("noise calibration: ") + e.what());
  }
}

std::optional<BlockSandwich> SandwichOverBlocks(const std::vector<std::vector<double>>& gradient, int width,
                                               const std::vector<double>& inverse_h, int requested,
                                               const std::vector<std::vector<double>>& summed) {
  const int d = int(gradient.size());
  if (d == 0 || width <= 0 || requested < 0 || inverse_h.size() != size_t(d) * d) return std::nullopt;
  const size_t texels = gradient[0].size();
  for (const std::vector<double>& g : gradient)
    if (g.size() != texels) return std::nullopt;
  Eigen::MatrixXd j_summed = Eigen::MatrixXd::Zero(d, d);
  int summed_blocks = 0;
  for (const std::vector<double>& block : summed) {
    if (block.size() != size_t(d)) return std::nullopt;
    const Eigen::Map<const Eigen::VectorXd> g(block.data(), d);
    if (g.squaredNorm() == 0.0) continue;
    j_summed += g * g.transpose();
    ++summed_blocks;
  }
  const int height = int(texels / size_t(width));
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> h_inverse(
      inverse_h.data(), d, d);
  std::vector<int> sides(std::begin(kSandwichBlockSides), std::end(kSandwichBlockSides));
  if (requested != kSandwichBlocksAuto) sides = {requested};
  std::optional<BlockSandwich> chosen;
  for (const int side : sides) {
    Eigen::MatrixXd j = j_summed;
    int blocks = summed_blocks;
    for (int by = 0; by < height; by += side)
      for (int bx = 0; bx < width; bx += side) {
        Eigen::VectorXd g = Eigen::VectorXd::Zero(d);
        for (int y = by; y < std::min(height, by + side); ++y)
          for (int x = bx; x < std::min(width, bx + side); ++x)
            for (int i = 0; i < d; ++i) g[i] += gradient[size_t(i)][size_t(y) * width + x];
        if (g.squaredNorm() == 0.0) continue;
        j += g * g.transpose();
        ++blocks;
      }
    // The smallest blocks need 2d to estimate J at all; a larger size must leave twice that,
    // or its estimate is noisy enough that taking the largest κ would mostly pick noise.
    const int needed = (side == sides[0] ? 2 : 4) * d;
    if (blocks < needed) {  // larger blocks leave fewer still
      if (!chosen) chosen = BlockSandwich{1.0, 1.0, 1.0, blocks, side};  // too few for J: κ stays 1
      break;
    }
    const Eigen::MatrixXd m = h_inverse * j;
    const Eigen::VectorXcd eigen = m.eigenvalues();
    const double kappa = std::clamp(m.trace() / double(d), 1e-3, 1e6);
    if (!chosen || kappa > chosen->kappa)
      chosen = BlockSandwich{kappa, eigen.real().minCoeff(), eigen.real().maxCoeff(), blocks, side,
                             std::vector<double>(j.data(), j.data() + j.size())};
  }
  return chosen;
}

namespace {

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

// κ from the per-texel score at ψ (finite differences over ± one sd of each parameter).
void SandwichFactor(Likelihood& likelihood, const std::vector<double>& psi, const Eigen::MatrixXd& inverse_h,
                    int sandwich_blocks, bool curvature_adjustment, NoiseCalibration* c) {
  const int d = int(psi.size());
  const bool correction = likelihood.model().chi2_correction;
  std::vector<std::vector<double>> gradient(static_cast<size_t>(d));  // per parameter, per texel
  std::vector<std::vector<double>> edge_blocks;  // per camera and model edge, per parameter
  int width = 0;
  for (int i = 0; i < d; ++i) {
    const double h = std::sqrt(std::max(inverse_h(i, i), 0.0));
    if (!(h > 0.0) || !std::isfinite(h)) return;
    std::vector<double> plus = psi, minus = psi;
    plus[size_t(i)] += h;
    minus[size_t(i)] -= h;
    const LikelihoodDump dump_up = likelihood.EvaluateAndDump(plus, nullptr);
    const LikelihoodDump dump_down = likelihood.EvaluateAndDump(minus, nullptr);
    const std::vector<double> up = TexelLogLikelihood(dump_up, correction, &width);
    const std::vector<double> down = TexelLogLikelihood(dump_down, correction, &width);
    if (up.empty() || up.size() != down.size()) return;
    gradient[size_t(i)].resize(up.size());
    for (size_t t = 0; t < up.size(); ++t) gradient[size_t(i)][t] = (up[t] - down[t]) / (2.0 * h);
    // The edge term's score, one block per camera and edge: its samples along an edge share
    // whatever the model does not explain there.
    const Image* edges_up = FindImage(dump_up, "edges");
    const Image* edges_down = FindImage(dump_down, "edges");
    if (edges_up && edges_down && edges_up->rgba.size() == edges_down->rgba.size()) {
      const size_t count = edges_up->rgba.size() / 4;
      edge_blocks.resize(count, std::vector<double>(size_t(d), 0.0));
      for (size_t k = 0; k < count; ++k)
        edge_blocks[k][size_t(i)] = (double(edges_up->rgba[4 * k]) - double(edges_down->rgba[4 * k])) / (2.0 * h);
    }
  }
  std::vector<double> inverse(size_t(d) * d);
  for (int i = 0; i < d; ++i)
    for (int k = 0; k < d; ++k) inverse[size_t(i) * d + k] = inverse_h(i, k);
  if (const std::optional<BlockSandwich> s = SandwichOverBlocks(gradient, width, inverse, sandwich_blocks, edge_blocks)) {
    c->kappa = s->kappa;
    c->kappa_min = s->kappa_min;
    c->kappa_max = s->kappa_max;
    c->blocks = s->blocks;
    c->block = s->block;
    if (curvature_adjustment && !s->j.empty()) {
      c->adjusted_curvature = AdjustedCurvature(inverse, s->j);
      if (c->CurvatureAdjusted()) {
        const Eigen::MatrixXd h = inverse_h.inverse();
        c->raw_curvature.assign(h.data(), h.data() + h.size());  // symmetric: either order
        c->adjustment_centre = psi;
      }
    }
  }
}

}  // namespace

namespace {

// σ and δ such that χ = N over all texels and over the textured ones (NoiseCalibration.h).
// A texel whose noise model puts a share u of its variance on the texture term has
// χ/d ≈ (1 − u)·s + u·r when the true σ² and δ² are s and r times the model's; the two
// weighted sums give s and r, and a few rounds settle the robust loss and the weights.
void EstimateSigmaAndDelta(Likelihood& likelihood, const std::vector<double>& psi, double sigma_floor,
                           NoiseCalibration* c) {
  constexpr double kMinDelta = 0.05, kMaxDelta = 4.0;  // pixels
  for (int round = 0; round < 6; ++round) {
    const LikelihoodDump dump = likelihood.EvaluateAndDump(psi, nullptr);
    const Image* deviation = FindImage(dump, "deviation");
    const Image* noise = FindImage(dump, "noise");
    if (!deviation) return;
    double a11 = 0, a12 = 0, a22 = 0, b1 = 0, b2 = 0;
    for (size_t t = 0; t < deviation->rgba.size(); t += 4) {
      const double chi = deviation->rgba[t], d = deviation->rgba[t + 1];
      if (!(d > 0.0)) continue;
      const double u = noise ? std::clamp(double(noise->rgba[t]), 0.0, 1.0) : 0.0;
      a11 += d * (1 - u), a12 += d * u, a22 += d * u * u, b1 += chi, b2 += u * chi;
    }
    if (!(a11 + a12 > 0.0)) return;
    // Σ d u(1−u) = a12 − a22.
    const double m11 = a11, m12 = a12, m21 = a12 - a22, m22 = a22;
    const double det = m11 * m22 - m12 * m21;
    double s = b1 / (a11 + a12), r = s;  // without texture to tell them apart: one factor
    if (noise && det > 1e-3 * (m11 + m22) * (m11 + m22)) {
      s = (b1 * m22 - m12 * b2) / det;
      r = (m11 * b2 - m21 * b1) / det;
    }
    if (!(s > 0.0)) s = 1e-2;
    if (!(r > 0.0)) r = 1e-2;
    const double sigma = std::max(c->sigma * std::sqrt(s), sigma_floor);
    const double delta = std::clamp(c->position_sd * std::sqrt(r), kMinDelta, kMaxDelta);
    const bool settled = std::abs(sigma - c->sigma) < 1e-3 * c->sigma && std::abs(delta - c->position_sd) < 1e-3 * c->position_sd;
    c->sigma = sigma;
    c->position_sd = delta;
    likelihood.SetSigma(c->sigma);
    likelihood.SetPositionSd(c->position_sd);
    if (settled) return;
  }
}

}  // namespace

NoiseCalibration CalibrateNoise(Likelihood& likelihood, const std::vector<double>& psi,
                                const std::vector<double>& covariance, double current_kappa,
                                bool estimate_sigma, bool mask_clutter, int sandwich_blocks, double sigma_floor,
                                bool curvature_adjustment) {
  const int level = likelihood.level();
  likelihood.SetLevel(0);
  NoiseCalibration c;
  // The masks are found anew, with the colour correction and σ fitted to every pixel, so a
  // calibration depends on ψ alone: a σ estimated with the last masks in place is smaller,
  // finds more clutter, and masking that makes σ smaller still — on Merton's photographs the
  // masked share grew 0.9 % → 4.2 % over eight calibrations at one mode, and κ never
  // settled (17.7 → 450 → 10.8 → 286 → … → 31,500).
  if (mask_clutter) likelihood.ClearClutterMasks();
  c.photometric = likelihood.CalibratePhotometric(psi);
  const double sigma_before = likelihood.model().sigma;
  c.sigma = sigma_before;
  c.position_sd = likelihood.model().position_sd;
  c.sigma_estimated = estimate_sigma;
  const double delta_before = c.position_sd;
  if (estimate_sigma) EstimateSigmaAndDelta(likelihood, psi, sigma_floor, &c);
  if (mask_clutter) {
    c.clutter = likelihood.MaskClutter(psi);
    if (estimate_sigma && !c.clutter.masks.empty()) EstimateSigmaAndDelta(likelihood, psi, sigma_floor, &c);
  }
  // The same deviations (final correction and masks) under the old and the new noise model.
  likelihood.SetSigma(sigma_before);
  likelihood.SetPositionSd(delta_before);
  const ReducedScalars before = likelihood.Evaluate({psi})[0].scalars;
  likelihood.SetSigma(c.sigma);
  likelihood.SetPositionSd(c.position_sd);
  const Evaluation at_psi = likelihood.Evaluate({psi})[0];
  const ReducedScalars& after = at_psi.scalars;
  c.chi2_per_dof = Chi2PerDof(after, c.sigma);
  c.centre_total = at_psi.total();
  const size_t d = psi.size();
  if (covariance.size() == d * d && d > 0) {
    const NoiseCorrelationEstimate noise = likelihood.NoiseCorrelation(psi);
    c.kappa_noise = noise.kappa;
    c.noise_rings = noise.rings;
    // The curvature of the raw log-likelihood under the new noise model: undo κ, and scale
    // by how much the noise model changed the χ² of the same deviations (its precisions
    // changed by about that much; for σ alone it is σ²_before/σ²; the N term has no curvature).
    Eigen::MatrixXd inverse_h(d, d);
    for (size_t i = 0; i < d; ++i)
      for (size_t k = 0; k < d; ++k) inverse_h(Eigen::Index(i), Eigen::Index(k)) = covariance[i * d + k];
    const double chi_before = before.sum_squares / std::pow(sigma_before / 255.0, 2);
    const double chi_after = after.sum_squares / std::pow(c.sigma / 255.0, 2);
    const double precision_ratio = chi_before > 0.0 && chi_after > 0.0 ? chi_after / chi_before : 1.0;
    inverse_h *= 1.0 / precision_ratio / current_kappa;
    SandwichFactor(likelihood, psi, inverse_h, sandwich_blocks, curvature_adjustment, &c);
  }
  likelihood.SetLevel(level);
  return c;
}

}  // namespace vkr
