#pragma once
// A tiny line-plot rasteriser for diagnostics (`vkrecon likelihood --sweep` plots log-likelihood
// against one parameter): white background, an axes box with "nice" ticks and numeric tick
// labels in a 5×7 bitmap font, one polyline with dots at the samples, and an optional vertical
// marker. No dependency beyond Image; write the result with WritePng.

#include <array>
#include <optional>
#include <span>

#include "engine/image/Image.h"

namespace vkr {

struct LinePlotOptions {
  int width = 640, height = 400;     // image size in pixels (at least 120 × 80)
  std::optional<double> marker_x;    // a vertical marker at this data x (kept inside the x range)
  bool tick_labels = true;           // numbers beside the ticks
  bool points = true;                // a dot at every sample as well as the line
  std::array<float, 3> line_colour = {0.10f, 0.25f, 0.75f};
  std::array<float, 3> marker_colour = {0.85f, 0.10f, 0.10f};
};

// Where data lands in the image: the plot area (pixel columns left..right and rows
// top..bottom, inclusive, inside the axes box) and the data ranges it spans.
struct LinePlotFrame {
  int left = 0, top = 0, right = 0, bottom = 0;
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  // Continuous pixel coordinates (pixel (i, j) spans [i, i+1)); y grows downwards.
  double PixelX(double x) const;
  double PixelY(double y) const;
};

struct LinePlot {
  Image image;  // encoded colours, alpha 1
  LinePlotFrame frame;
};

// Plots y against x (same length, x in any order: the polyline joins samples in the order
// given). Non-finite samples are skipped and break the line. The x range spans the data and
// the marker; the y range spans the finite data with a 5 % margin (± 1 around a constant).
// Throws std::invalid_argument when the lengths differ or the size is too small.
LinePlot PlotLine(std::span<const double> x, std::span<const double> y,
                  const LinePlotOptions& options = {});

}  // namespace vkr
