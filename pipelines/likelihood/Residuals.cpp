#include "pipelines/likelihood/Residuals.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <locale>
#include <stdexcept>

namespace vkr {
std::vector<NodeResidual> NodeResiduals(const Scene& scene, const AtlasLayout& atlas, const Image& deviation_image,
                                        const Image& noise_image) {
  const Image* deviation = &deviation_image;
  const Image* noise = &noise_image;
  if (deviation->width != noise->width || deviation->height != noise->height)
    throw std::invalid_argument("NodeResiduals: deviation and noise images of different sizes");
  const int side = deviation->width;
  const double scale = double(side) / atlas.size;  // the dump's level

  std::vector<int> slot(scene.nodes.size(), -1);  // node → entry (charts come in node order)
  std::vector<NodeResidual> out;
  for (const Chart& chart : atlas.charts) {
    if (slot[size_t(chart.node)] < 0) {
      slot[size_t(chart.node)] = int(out.size());
      out.push_back(NodeResidual{scene.nodes[size_t(chart.node)].name});
    }
    NodeResidual& r = out[size_t(slot[size_t(chart.node)])];
    const int x0 = std::max(0, int(std::floor(chart.x * scale))), x1 = std::min(side, int(std::ceil((chart.x + chart.w) * scale)));
    const int y0 = std::max(0, int(std::floor(chart.y * scale))), y1 = std::min(side, int(std::ceil((chart.y + chart.h) * scale)));
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const float* d = deviation->At(x, y);
        const float* n = noise->At(x, y);
        if (d[3] == 0.0f || d[2] != 0.0f) continue;  // off the surface, or interior
        ++r.texels;
        const int views = int(std::lround(n[2]));
        if (views < 2 && n[3] > 0.5f) ++r.masked;
        else if (views == 0) ++r.seen_none;
        else if (views == 1) ++r.seen_once;
        else {
          ++r.compared;
          r.chi2 += d[0];
          r.expected += d[1];
          r.views += views;
          r.outlier_views += int(std::lround(n[1]));
        }
      }
  }
  return out;
}

NodeResidual TotalResidual(const std::vector<NodeResidual>& nodes) {
  NodeResidual t{"all"};
  for (const NodeResidual& r : nodes) {
    t.texels += r.texels, t.compared += r.compared, t.seen_once += r.seen_once, t.seen_none += r.seen_none;
    t.masked += r.masked;
    t.chi2 += r.chi2, t.expected += r.expected, t.views += r.views, t.outlier_views += r.outlier_views;
  }
  return t;
}

void WriteNodeResidualsCsv(const std::filesystem::path& file, const std::vector<NodeResidual>& nodes) {
  std::ofstream out(file);
  out.imbue(std::locale::classic());
  out.precision(10);
  out << "node,texels,compared,seen_once,seen_none,masked,chi2,expected,chi2_per_dof,views,outlier_views,"
         "outlier_share\n";
  std::vector<NodeResidual> rows = nodes;
  rows.push_back(TotalResidual(nodes));
  for (const NodeResidual& r : rows)
    out << r.node << ',' << r.texels << ',' << r.compared << ',' << r.seen_once << ',' << r.seen_none << ','
        << r.masked << ','
        << r.chi2 << ',' << r.expected << ',' << r.Chi2PerDof() << ',' << r.views << ',' << r.outlier_views << ','
        << r.OutlierShare() << '\n';
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

}  // namespace vkr
