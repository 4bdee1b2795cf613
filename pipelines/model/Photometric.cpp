#include "pipelines/model/Photometric.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace vkr {

const char* ToString(PhotometricModel model) {
  switch (model) {
    case PhotometricModel::None: return "none";
    case PhotometricModel::Gain: return "gain";
    case PhotometricModel::Affine: return "affine";
  }
  return "none";
}

bool FromString(const std::string& text, PhotometricModel* model) {
  for (PhotometricModel m : {PhotometricModel::None, PhotometricModel::Gain, PhotometricModel::Affine})
    if (text == ToString(m)) {
      *model = m;
      return true;
    }
  return false;
}

PhotometricCorrection PhotometricCorrection::Identity(int cameras) {
  PhotometricCorrection c;
  c.gain.assign(size_t(cameras), {1.0, 1.0, 1.0});
  c.offset.assign(size_t(cameras), {0.0, 0.0, 0.0});
  return c;
}

bool PhotometricCorrection::IsIdentity() const {
  for (size_t i = 0; i < gain.size(); ++i)
    for (int c = 0; c < 3; ++c)
      if (gain[i][size_t(c)] != 1.0 || offset[i][size_t(c)] != 0.0) return false;
  return true;
}

nlohmann::json ToJson(const PhotometricCorrection& correction) {
  return {{"gain", correction.gain}, {"offset", correction.offset}};
}

PhotometricCorrection PhotometricFromJson(const nlohmann::json& json, int cameras) {
  try {
    PhotometricCorrection c;
    c.gain = json.at("gain").get<std::vector<std::array<double, 3>>>();
    c.offset = json.at("offset").get<std::vector<std::array<double, 3>>>();
    if (c.cameras() != cameras || int(c.offset.size()) != cameras)
      throw std::invalid_argument("photometric correction for " + std::to_string(c.cameras()) + " cameras, not " +
                                  std::to_string(cameras));
    for (int i = 0; i < cameras; ++i)
      for (int k = 0; k < 3; ++k)
        if (!(c.gain[size_t(i)][size_t(k)] > 0.0) || !std::isfinite(c.offset[size_t(i)][size_t(k)]))
          throw std::invalid_argument("photometric correction out of range");
    return c;
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(std::string("photometric correction: ") + e.what());
  }
}

namespace {

// Weighted first and second moments of paired samples (a camera's colour x, the others'
// consensus y) in one channel.
struct Moments {
  double w = 0, x = 0, y = 0, xx = 0, yy = 0;
  int count = 0;
  void Add(double weight, double xi, double yi) {
    w += weight;
    x += weight * xi;
    y += weight * yi;
    xx += weight * xi * xi;
    yy += weight * yi * yi;
    ++count;
  }
};

}  // namespace

PhotometricCorrection FitPhotometric(const std::vector<Image>& views, PhotometricModel model, int rounds,
                                     int min_texels) {
  const int n = int(views.size());
  PhotometricCorrection fit = PhotometricCorrection::Identity(n);
  if (model == PhotometricModel::None || n < 2) return fit;
  const size_t texels = views[0].rgba.size() / 4;
  for (const Image& v : views)
    if (v.rgba.size() != views[0].rgba.size()) throw std::invalid_argument("FitPhotometric: views of different sizes");

  std::vector<double> corrected(static_cast<size_t>(n) * 3);
  std::vector<double> weight(static_cast<size_t>(n));
  for (int round = 0; round < rounds; ++round) {
    // Residuals of each camera from the others' consensus, for a robust scale per camera.
    std::vector<std::vector<float>> residuals(static_cast<size_t>(n));
    std::vector<std::array<Moments, 3>> moments(static_cast<size_t>(n));
    for (int pass = 0; pass < 2; ++pass) {
      std::vector<double> scale(static_cast<size_t>(n), INFINITY);
      if (pass == 1)
        for (int i = 0; i < n; ++i) {
          std::vector<float>& r = residuals[size_t(i)];
          if (r.empty()) continue;
          std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
          scale[size_t(i)] = 4.0 * 1.4826 * double(r[r.size() / 2]) + 1e-6;  // 4 robust sds
        }
      for (size_t t = 0; t < texels; ++t) {
        double sum_w = 0, sum_wc[3] = {0, 0, 0};
        int seen = 0;
        for (int i = 0; i < n; ++i) {
          const float* p = &views[size_t(i)].rgba[t * 4];
          weight[size_t(i)] = p[3] > 0.0f ? double(p[3]) : 0.0;
          if (weight[size_t(i)] == 0.0) continue;
          ++seen;
          sum_w += weight[size_t(i)];
          for (int c = 0; c < 3; ++c) {
            const double v = fit.gain[size_t(i)][size_t(c)] * p[c] + fit.offset[size_t(i)][size_t(c)];
            corrected[size_t(i) * 3 + size_t(c)] = v;
            sum_wc[c] += weight[size_t(i)] * v;
          }
        }
        if (seen < 2) continue;
        for (int i = 0; i < n; ++i) {
          const double wi = weight[size_t(i)];
          if (wi == 0.0) continue;
          const double others = sum_w - wi;  // leave-one-out: a camera is not its own reference
          double consensus[3], distance = 0.0;
          for (int c = 0; c < 3; ++c) {
            consensus[c] = (sum_wc[c] - wi * corrected[size_t(i) * 3 + size_t(c)]) / others;
            distance = std::max(distance, std::abs(corrected[size_t(i) * 3 + size_t(c)] - consensus[c]));
          }
          if (pass == 0) {
            residuals[size_t(i)].push_back(float(distance));
          } else if (distance <= scale[size_t(i)]) {
            const float* p = &views[size_t(i)].rgba[t * 4];
            for (int c = 0; c < 3; ++c) moments[size_t(i)][size_t(c)].Add(wi * others / sum_w, p[c], consensus[c]);
          }
        }
      }
    }
    PhotometricCorrection next = fit;
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        const Moments& m = moments[size_t(i)][size_t(c)];
        if (m.count < min_texels || !(m.w > 0.0)) continue;
        const double mx = m.x / m.w, my = m.y / m.w;
        if (model == PhotometricModel::Gain) {
          if (mx > 1e-3) next.gain[size_t(i)][size_t(c)] = my / mx, next.offset[size_t(i)][size_t(c)] = 0.0;
        } else {
          const double sx = std::sqrt(std::max(m.xx / m.w - mx * mx, 0.0));
          const double sy = std::sqrt(std::max(m.yy / m.w - my * my, 0.0));
          if (sx > 1e-3) {
            next.gain[size_t(i)][size_t(c)] = sy / sx;
            next.offset[size_t(i)][size_t(c)] = my - sy / sx * mx;
          }
        }
      }
    // Gauge: average gain 1 and offset 0 per channel (the consensus could drift otherwise).
    for (int c = 0; c < 3; ++c) {
      double mean_gain = 0, mean_offset = 0;
      for (int i = 0; i < n; ++i) mean_gain += next.gain[size_t(i)][size_t(c)] / n, mean_offset += next.offset[size_t(i)][size_t(c)] / n;
      for (int i = 0; i < n; ++i) {
        next.gain[size_t(i)][size_t(c)] /= mean_gain;
        next.offset[size_t(i)][size_t(c)] = (next.offset[size_t(i)][size_t(c)] - mean_offset) / mean_gain;
      }
    }
    fit = next;
  }
  return fit;
}

}  // namespace vkr
