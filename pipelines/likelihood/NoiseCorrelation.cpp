#include "pipelines/likelihood/NoiseCorrelation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

#include "pipelines/likelihood/SurfaceLikelihood.h"

namespace vkr {

NoiseCorrelationEstimate ResidualCorrelation(const std::vector<Image>& residuals, int radius) {
  NoiseCorrelationEstimate out;
  out.radius = std::max(0, radius);
  const int side = 2 * out.radius + 1;
  // Σ e_t e_{t+lag} and the number of products, per lag of the half plane (dy > 0, or dy = 0
  // and dx ≥ 0); the other half mirrors it.
  std::vector<double> products(size_t(side) * side, 0.0), pairs(products.size(), 0.0);
  for (const Image& image : residuals) {
    const int w = image.width, h = image.height;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float* e = image.At(x, y);
        if (!(e[3] > 0.0f)) continue;
        out.samples += 3.0;
        for (int dy = 0; dy <= out.radius && y + dy < h; ++dy)
          for (int dx = dy == 0 ? 0 : -out.radius; dx <= out.radius; ++dx) {
            const int u = x + dx;
            if (u < 0 || u >= w) continue;
            const float* f = image.At(u, y + dy);
            if (!(f[3] > 0.0f)) continue;
            const size_t lag = size_t(dy + out.radius) * side + size_t(dx + out.radius);
            products[lag] += double(e[0]) * f[0] + double(e[1]) * f[1] + double(e[2]) * f[2];
            pairs[lag] += 3.0;
          }
      }
  }
  const size_t centre = size_t(out.radius) * side + size_t(out.radius);
  if (!(pairs[centre] > 0.0) || !(products[centre] > 0.0)) return out;
  const double variance = products[centre] / pairs[centre];
  std::vector<double> ring_sum(size_t(out.radius) + 1, 0.0), ring_count(ring_sum.size(), 0.0);
  double sum = 0.0;
  for (int dy = 0; dy <= out.radius; ++dy)
    for (int dx = -out.radius; dx <= out.radius; ++dx) {
      const size_t lag = size_t(dy + out.radius) * side + size_t(dx + out.radius);
      if (!(pairs[lag] > 0.0)) continue;
      const double rho = products[lag] / pairs[lag] / variance;
      const bool mirrored = lag != centre;  // (−dx, −dy) holds the same pairs
      sum += mirrored ? 2.0 * rho : rho;
      const int ring = std::max(std::abs(dx), dy);
      ring_sum[size_t(ring)] += mirrored ? 2.0 * rho : rho;
      ring_count[size_t(ring)] += mirrored ? 2.0 : 1.0;
    }
  out.kappa = std::max(1.0, sum);
  for (size_t r = 0; r < ring_sum.size(); ++r) out.rings.push_back(ring_count[r] > 0 ? ring_sum[r] / ring_count[r] : 0.0);
  return out;
}

double StandardisedResidual(const SurfaceDump& dump, int view, int x, int y, const LikelihoodModel& model,
                            const PhotometricCorrection& photometric, double e[3]) {
  const float* c = dump.view_textures[size_t(view)].At(x, y);
  const float* mean = dump.composite.At(x, y);
  if (!(c[3] > 0.0f) || mean[3] < 2.0f) return -1.0;  // unseen by this view, or by no other
  const bool corrected = view < photometric.cameras();
  const std::array<double, 3> unit_gain{1.0, 1.0, 1.0}, zero{0.0, 0.0, 0.0};
  const std::array<double, 3>& gain = corrected ? photometric.gain[size_t(view)] : unit_gain;
  const std::array<double, 3>& offset = corrected ? photometric.offset[size_t(view)] : zero;
  // The noise model's variance (Evaluation.h): σ² over the pixels the sample averages, plus
  // δ²|∇I|² with the gradient as this view's correction scales it.
  const float* noise = dump.view_noise[size_t(view)].At(x, y);
  const double g = (gain[0] + gain[1] + gain[2]) / 3.0 * noise[0];
  const double mass = std::max(1.0, double(noise[1]));
  const double sd = std::sqrt(std::pow(model.sigma / 255.0, 2) / mass + model.position_sd * model.position_sd * g * g);
  if (!(sd > 0.0)) return -1.0;
  double e2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    e[k] = (gain[size_t(k)] * c[k] + offset[size_t(k)] - mean[k]) / sd;
    e2 += e[k] * e[k];
  }
  return e2;
}

std::vector<Image> StandardisedResiduals(const SurfaceDump& dump, const LikelihoodModel& model,
                                         const PhotometricCorrection& photometric) {
  std::vector<Image> out;
  for (size_t i = 0; i < dump.view_textures.size() && i < dump.view_noise.size(); ++i) {
    Image residual(dump.view_textures[i].width, dump.view_textures[i].height, 0.0f);
    for (int y = 0; y < residual.height; ++y)
      for (int x = 0; x < residual.width; ++x) {
        double e[3];
        const double e2 = StandardisedResidual(dump, int(i), x, y, model, photometric, e);
        if (e2 < 0.0) continue;
        float* r = residual.At(x, y);
        for (int k = 0; k < 3; ++k) r[k] = float(e[k]);
        r[3] = e2 > model.outlier_chi2 ? 0.0f : 1.0f;  // the composite's outlier rule
      }
    out.push_back(std::move(residual));
  }
  return out;
}

}  // namespace vkr
