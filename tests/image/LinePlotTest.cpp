// The line-plot rasteriser behind `vkrecon likelihood --sweep`: the polyline's pixels are where
// the data says, the marker column carries the marker colour, and the plot survives
// degenerate data.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "engine/image/LinePlot.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

bool IsWhite(const float* p) { return p[0] > 0.99f && p[1] > 0.99f && p[2] > 0.99f; }
bool IsLineColour(const float* p, const LinePlotOptions& o) {
  return std::abs(p[0] - o.line_colour[0]) < 1e-6f && std::abs(p[1] - o.line_colour[1]) < 1e-6f &&
         std::abs(p[2] - o.line_colour[2]) < 1e-6f;
}

// Counts line-coloured pixels in a square of side 2r+1 around (x, y).
int LinePixelsNear(const LinePlot& plot, const LinePlotOptions& o, double x, double y, int r = 3) {
  int n = 0;
  for (int j = int(y) - r; j <= int(y) + r; ++j)
    for (int i = int(x) - r; i <= int(x) + r; ++i)
      if (i >= 0 && j >= 0 && i < plot.image.width && j < plot.image.height &&
          IsLineColour(plot.image.At(i, j), o))
        ++n;
  return n;
}

// Counts line-coloured pixels in the rectangle [x0, x1] × [y0, y1].
int LinePixelsIn(const LinePlot& plot, const LinePlotOptions& o, int x0, int y0, int x1, int y1) {
  int n = 0;
  for (int j = y0; j <= y1; ++j)
    for (int i = x0; i <= x1; ++i) n += IsLineColour(plot.image.At(i, j), o);
  return n;
}

TEST(LinePlot, RisingLineRunsFromLowerLeftToUpperRight) {
  const std::vector<double> x = {0.0, 0.25, 0.5, 0.75, 1.0}, y = {0.0, 0.25, 0.5, 0.75, 1.0};
  LinePlotOptions o;
  o.points = false;
  const LinePlot plot = PlotLine(x, y, o);
  ASSERT_EQ(plot.image.width, 640);
  ASSERT_EQ(plot.image.height, 400);
  const LinePlotFrame& f = plot.frame;
  const int w = f.right - f.left, h = f.bottom - f.top;
  ASSERT_GT(w, 400);
  ASSERT_GT(h, 250);
  // Line pixels in the lower-left and upper-right quarters of the plot area ...
  const int cx = (f.left + f.right) / 2, cy = (f.top + f.bottom) / 2;
  EXPECT_GT(LinePixelsIn(plot, o, f.left, cy + 1, cx - 1, f.bottom), 100);
  EXPECT_GT(LinePixelsIn(plot, o, cx + 1, f.top, f.right, cy - 1), 100);
  // ... none in the upper-left and lower-right ones (but for the join at the centre), ...
  EXPECT_EQ(LinePixelsIn(plot, o, f.left, f.top, cx - 10, cy - 10), 0);
  EXPECT_EQ(LinePixelsIn(plot, o, cx + 10, cy + 10, f.right, f.bottom), 0);
  // ... and on the data all along it.
  for (double t = 0.05; t < 1.0; t += 0.1)
    EXPECT_GT(LinePixelsNear(plot, o, f.PixelX(t), f.PixelY(t), 1), 0) << "t = " << t;
  // The background is white and the axes box is dark.
  EXPECT_TRUE(IsWhite(plot.image.At(f.left + w / 2 + 3, f.top + 5)));
  const float* box = plot.image.At((f.left + f.right) / 2, f.bottom + 1);
  EXPECT_LT(box[0] + box[1] + box[2], 1.0f);
  // The y range has a margin: the first sample sits above the bottom edge.
  EXPECT_LT(f.y_min, 0.0);
  EXPECT_GT(f.y_max, 1.0);
  EXPECT_DOUBLE_EQ(f.x_min, 0.0);
  EXPECT_DOUBLE_EQ(f.x_max, 1.0);
}

TEST(LinePlot, MarkerColumnIsColoured) {
  const std::vector<double> x = {-1.0, 0.0, 1.0}, y = {5.0, 7.0, 5.0};
  LinePlotOptions o;
  o.marker_x = 0.5;
  const LinePlot plot = PlotLine(x, y, o);
  const LinePlotFrame& f = plot.frame;
  const int column = int(std::floor(f.PixelX(0.5)));
  int marked = 0;
  for (int j = f.top; j <= f.bottom; ++j) {
    const float* p = plot.image.At(column, j);
    if (std::abs(p[0] - o.marker_colour[0]) < 1e-6f && std::abs(p[1] - o.marker_colour[1]) < 1e-6f) ++marked;
  }
  // All of the column but where the line crosses it.
  EXPECT_GT(marked, (f.bottom - f.top) * 9 / 10);
  // Columns away from the marker are not marker-coloured.
  const float* away = plot.image.At(int(f.PixelX(-0.5)), f.top + 2);
  EXPECT_FALSE(std::abs(away[0] - o.marker_colour[0]) < 1e-6f && std::abs(away[1] - o.marker_colour[1]) < 1e-6f);
}

TEST(LinePlot, MarkerOutsideTheDataWidensTheRange) {
  const std::vector<double> x = {0.0, 1.0}, y = {0.0, 1.0};
  LinePlotOptions o;
  o.marker_x = 3.0;
  const LinePlot plot = PlotLine(x, y, o);
  EXPECT_DOUBLE_EQ(plot.frame.x_max, 3.0);
}

TEST(LinePlot, DegenerateDataStillPlots) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> x = {0.0, 1.0, 2.0, 3.0}, flat = {2.0, 2.0, nan, 2.0};
  const LinePlot plot = PlotLine(x, flat);
  EXPECT_LT(plot.frame.y_min, 2.0);
  EXPECT_GT(plot.frame.y_max, 2.0);
  EXPECT_NO_THROW(PlotLine(std::vector<double>{}, std::vector<double>{}));
  EXPECT_THROW(PlotLine(x, std::vector<double>{1.0}), std::invalid_argument);
  LinePlotOptions tiny;
  tiny.width = 10;
  EXPECT_THROW(PlotLine(x, flat, tiny), std::invalid_argument);
}

TEST(LinePlot, WritesAReadablePng) {
  test::TempDir dir;
  const std::vector<double> x = {-2e5, 0.0, 3e5}, y = {-1.5e6, -1.2e6, -1.9e6};
  LinePlotOptions o;
  o.marker_x = 1e5;
  const LinePlot plot = PlotLine(x, y, o);
  WritePng(dir / "plot.png", plot.image);
  const Image back = LoadImage(dir / "plot.png");
  EXPECT_EQ(back.width, 640);
  EXPECT_EQ(back.height, 400);
  // Tick labels draw dark pixels left of the plot area.
  int dark = 0;
  for (int j = 0; j < back.height; ++j)
    for (int i = 0; i < plot.frame.left - 5; ++i)
      if (back.At(i, j)[0] < 0.5f) ++dark;
  EXPECT_GT(dark, 20);
}

}  // namespace
}  // namespace vkr
