#include "pipelines/model/EdgeEvidence.h"

#include <algorithm>
#include <cmath>

namespace vkr {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

double EdgeLogRatio(const Eigen::Vector3d& delta, double variance, double clutter, double hidden) {
  // r = (1−ε) N(Δ)/U, with U = 1; in logs, so that a tiny variance cannot overflow.
  const double log_r =
      std::log1p(-clutter) - 1.5 * std::log(2.0 * kPi * variance) - delta.squaredNorm() / (2.0 * variance);
  if (log_r > 50.0) {  // no-edge explains Δ by far: the ratio is η + O(1/r)
    const double r = std::exp(log_r);
    return std::log(hidden + (1.0 - hidden + hidden * clutter) / r) - std::log1p(clutter / r);
  }
  const double p0 = std::exp(log_r) + clutter;  // p₀/U
  return std::log((1.0 - hidden) + hidden * p0) - std::log(p0);
}

double ContrastThreshold(double variance) {
  // N(Δ; 0, v) = 1  ⇔  |Δ|² = −3 v log(2π v). Where noise is so large that this falls below
  // the 99th percentile of |Δ|²/v (χ² with 3 degrees of freedom, 11.34), the percentile
  // holds: a share of pairs noise explains must not pass for clutter.
  return variance * std::max(-3.0 * std::log(2.0 * kPi * variance), 11.345);
}

PairContrasts::PairContrasts(const Image& image, const Image& validity, size_t keep) {
  auto valid = [&](int x, int y) { return validity.Empty() || validity.At(x, y)[0] >= 0.5f; };
  auto contrast = [&](int x0, int y0, int x1, int y1) {
    const float* a = image.At(x0, y0);
    const float* b = image.At(x1, y1);
    float sum = 0.0f;
    for (int c = 0; c < 3; ++c) sum += (a[c] - b[c]) * (a[c] - b[c]);
    return sum;
  };
  // A photograph of many megapixels holds tens of millions of pairs: every stride-th pixel's
  // pairs still leave eight times `keep`, enough for the quantiles, and sort in milliseconds.
  const size_t pixels = size_t(image.width) * size_t(image.height);
  const size_t stride = std::max<size_t>(1, 2 * pixels / (8 * std::max<size_t>(keep, 1)));
  std::vector<float> all;
  all.reserve(2 * pixels / stride + 2);
  for (size_t k = 0; k < pixels; k += stride) {
    const int x = int(k % size_t(image.width)), y = int(k / size_t(image.width));
    if (!valid(x, y)) continue;
    if (x + 1 < image.width && valid(x + 1, y)) all.push_back(contrast(x, y, x + 1, y));
    if (y + 1 < image.height && valid(x, y + 1)) all.push_back(contrast(x, y, x, y + 1));
  }
  std::sort(all.begin(), all.end());
  if (all.size() <= keep) {
    sorted_ = std::move(all);
    return;
  }
  // Every (n/keep)-th of the sorted values: the same quantiles, to within 1/keep.
  sorted_.reserve(keep);
  for (size_t k = 0; k < keep; ++k) sorted_.push_back(all[(2 * k + 1) * all.size() / (2 * keep)]);
}

double PairContrasts::ShareAbove(double threshold) const {
  if (sorted_.empty()) return 0.0;
  const auto first = std::upper_bound(sorted_.begin(), sorted_.end(), float(threshold));
  return double(sorted_.end() - first) / double(sorted_.size());
}

double ClutterShare(const PairContrasts& pairs, double variance, const EdgeModel& model) {
  return std::clamp(pairs.ShareAbove(ContrastThreshold(variance)), model.min_clutter, model.max_clutter);
}

}  // namespace vkr
