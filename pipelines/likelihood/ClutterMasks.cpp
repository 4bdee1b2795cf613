#include "pipelines/likelihood/ClutterMasks.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "pipelines/likelihood/NoiseCorrelation.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"
#include "pipelines/rendering/ViewRendering.h"

namespace vkr {
namespace {

// Per texel of the dump's atlas, whether camera i's view is an outlier of the consensus
// (r), and whether camera i sees the texel at all (g); b = 0, a = 1.
Image OutlierAtlas(const SurfaceDump& dump, int i, const LikelihoodModel& model, const PhotometricCorrection& photometric,
                   double threshold) {
  const Image& view = dump.view_textures[size_t(i)];
  Image out(view.width, view.height, 0.0f);
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      float* o = out.At(x, y);
      o[3] = 1.0f;
      double e[3];
      const double e2 = StandardisedResidual(dump, i, x, y, model, photometric, e);
      if (e2 < 0.0) continue;  // not seen by this view, or by fewer than two
      o[0] = e2 > threshold ? 1.0f : 0.0f;  // composite.comp's outlier rule
      o[1] = 1.0f;
    }
  return out;
}

// Box sums over (2r+1)² windows, clamped at the borders (a summed-area table).
std::vector<double> BoxSums(const std::vector<double>& v, int w, int h, int r) {
  std::vector<double> table(size_t(w + 1) * (h + 1), 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      table[size_t(y + 1) * (w + 1) + x + 1] = v[size_t(y) * w + x] + table[size_t(y) * (w + 1) + x + 1] +
                                               table[size_t(y + 1) * (w + 1) + x] - table[size_t(y) * (w + 1) + x];
  std::vector<double> out(v.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int x0 = std::max(0, x - r), x1 = std::min(w, x + r + 1), y0 = std::max(0, y - r), y1 = std::min(h, y + r + 1);
      out[size_t(y) * w + x] = table[size_t(y1) * (w + 1) + x1] - table[size_t(y0) * (w + 1) + x1] -
                               table[size_t(y1) * (w + 1) + x0] + table[size_t(y0) * (w + 1) + x0];
    }
  return out;
}

}  // namespace

ClutterMasks FindClutter(vk::Device& device, SurfaceLikelihood& likelihood, const std::vector<double>& psi,
                         const ClutterOptions& options) {
  const Scene& scene = likelihood.scene();
  const SceneGeometry& geometry = likelihood.geometry();
  const LikelihoodModel& model = likelihood.options().model;
  const PhotometricCorrection& photometric = likelihood.photometric();
  const int level = likelihood.level();
  likelihood.SetLevel(0);
  likelihood.ClearClutterMasks();
  const SurfaceDump dump = likelihood.EvaluateAndDump(psi);
  likelihood.SetLevel(level);
  const int n = int(scene.cameras.size());
  if (int(dump.view_textures.size()) != n || int(dump.view_noise.size()) != n || photometric.cameras() != n)
    throw std::invalid_argument("FindClutter: a dump and a correction for every camera are needed");
  if (dump.composite.width != geometry.atlas.size)
    throw std::invalid_argument("FindClutter: the dump must be of level 0");
  const std::vector<Camera> cameras = scene.Cameras(psi);
  ClutterMasks out;
  for (int i = 0; i < n; ++i) {
    const Image atlas = OutlierAtlas(dump, i, model, photometric, options.outlier_factor * model.outlier_chi2);
    const Image drawn = RenderWithAtlas(device, scene, psi, geometry, atlas, {cameras[size_t(i)]})[0];
    const int w = drawn.width, h = drawn.height;
    // Outliers per covered pixel; a majority of its window makes a pixel part of a region.
    std::vector<double> outlier(size_t(w) * h, 0.0), covered(outlier.size(), 0.0);
    for (size_t p = 0; p < outlier.size(); ++p) {
      const float* d = &drawn.rgba[4 * p];
      if (d[3] > 0.0f && d[1] > 0.5f) covered[p] = 1.0, outlier[p] = d[0] / d[1];
    }
    const std::vector<double> outliers = BoxSums(outlier, w, h, options.majority_radius);
    const std::vector<double> coverage = BoxSums(covered, w, h, options.majority_radius);
    std::vector<double> region(outlier.size(), 0.0);
    for (size_t p = 0; p < region.size(); ++p)
      region[p] = covered[p] > 0.0 && outliers[p] > 0.5 * coverage[p] ? 1.0 : 0.0;
    const std::vector<double> grown = BoxSums(region, w, h, options.grow);
    Image mask(w, h, 1.0f);
    double masked = 0.0, total = 0.0;
    for (size_t p = 0; p < region.size(); ++p) {
      total += covered[p];
      if (grown[p] > 0.0) {
        for (int c = 0; c < 3; ++c) mask.rgba[4 * p + size_t(c)] = 0.0f;  // black, opaque
        masked += covered[p];
      }
    }
    out.masks.push_back(std::move(mask));
    out.share.push_back(total > 0.0 ? masked / total : 0.0);
  }
  return out;
}

}  // namespace vkr
