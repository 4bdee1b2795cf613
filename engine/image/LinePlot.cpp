#include "engine/image/LinePlot.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace vkr {
namespace {

using Colour = std::array<float, 3>;
constexpr Colour kAxes = {0.15f, 0.15f, 0.15f};
constexpr Colour kGrid = {0.90f, 0.90f, 0.90f};

// 5×7 glyphs, one byte per row, bit 4 the leftmost column: enough for tick labels.
struct Glyph {
  char c;
  uint8_t rows[7];
};
constexpr Glyph kFont[] = {
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
    {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
    {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
    {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
    {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
    {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
    {'+', {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
    {'e', {0x00, 0x00, 0x0E, 0x11, 0x1F, 0x10, 0x0E}},
};
constexpr int kGlyphAdvance = 6;  // 5 columns + 1 of spacing

class Canvas {
 public:
  explicit Canvas(Image& image) : image_(image) {}
  void Set(int x, int y, const Colour& c) {
    if (x < 0 || y < 0 || x >= image_.width || y >= image_.height) return;
    float* p = image_.At(x, y);
    p[0] = c[0];
    p[1] = c[1];
    p[2] = c[2];
    p[3] = 1.0f;
  }
  void HLine(int x0, int x1, int y, const Colour& c) {
    for (int x = x0; x <= x1; ++x) Set(x, y, c);
  }
  void VLine(int x, int y0, int y1, const Colour& c) {
    for (int y = y0; y <= y1; ++y) Set(x, y, c);
  }
  // Text with its top-left corner at (x, y); unknown characters advance blank.
  void Text(int x, int y, const std::string& text, const Colour& c) {
    for (char ch : text) {
      for (const Glyph& g : kFont) {
        if (g.c != ch) continue;
        for (int row = 0; row < 7; ++row)
          for (int col = 0; col < 5; ++col)
            if (g.rows[row] & (0x10 >> col)) Set(x + col, y + row, c);
      }
      x += kGlyphAdvance;
    }
  }

 private:
  Image& image_;
};

int TextWidth(const std::string& text) { return int(text.size()) * kGlyphAdvance - 1; }

// 1, 2 or 5 times a power of ten, giving about `count` intervals over [lo, hi].
double NiceStep(double lo, double hi, int count) {
  const double raw = (hi - lo) / count;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  double best = power;
  for (double m : {2.0, 5.0, 10.0})
    if (std::abs(std::log(m * power / raw)) < std::abs(std::log(best / raw))) best = m * power;
  return best;
}

std::vector<double> Ticks(double lo, double hi, double step) {
  std::vector<double> ticks;
  for (double k = std::ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * step; k += 1.0)
    ticks.push_back(std::abs(k * step) < 1e-12 * step ? 0.0 : k * step);
  return ticks;
}

// Enough decimals to tell ticks `step` apart; exponent form for very large or small numbers.
std::string TickLabel(double value, double step) {
  char text[32];
  const double magnitude = std::max(std::abs(value), step);
  if (magnitude >= 1e7 || step < 1e-5) {
    std::snprintf(text, sizeof text, "%.3g", value);
  } else {
    const int decimals = std::max(0, int(std::ceil(-std::log10(step) - 1e-9)));
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
  }
  return text;
}

// Stamps a disc of `radius` pixels at continuous position (x, y), clipped to the frame.
void Dot(Canvas& canvas, const LinePlotFrame& f, double x, double y, double radius, const Colour& c) {
  for (int iy = int(std::floor(y - radius)); iy <= int(std::ceil(y + radius)); ++iy)
    for (int ix = int(std::floor(x - radius)); ix <= int(std::ceil(x + radius)); ++ix) {
      if (ix < f.left || ix > f.right || iy < f.top || iy > f.bottom) continue;
      const double dx = ix + 0.5 - x, dy = iy + 0.5 - y;
      if (dx * dx + dy * dy <= radius * radius) canvas.Set(ix, iy, c);
    }
}

void Segment(Canvas& canvas, const LinePlotFrame& f, double x0, double y0, double x1, double y1,
             const Colour& c) {
  const int steps = 1 + int(std::ceil(2.0 * std::max(std::abs(x1 - x0), std::abs(y1 - y0))));
  for (int s = 0; s <= steps; ++s) {
    const double t = double(s) / steps;
    Dot(canvas, f, x0 + t * (x1 - x0), y0 + t * (y1 - y0), 1.1, c);
  }
}

}  // namespace

double LinePlotFrame::PixelX(double x) const {
  return left + (x - x_min) / (x_max - x_min) * (right + 1 - left);
}

double LinePlotFrame::PixelY(double y) const {
  return top + (y_max - y) / (y_max - y_min) * (bottom + 1 - top);
}

LinePlot PlotLine(std::span<const double> x, std::span<const double> y, const LinePlotOptions& options) {
  if (x.size() != y.size())
    throw std::invalid_argument("PlotLine: " + std::to_string(x.size()) + " x values but " +
                                std::to_string(y.size()) + " y values");
  if (options.width < 120 || options.height < 80)
    throw std::invalid_argument("PlotLine: image smaller than 120×80");

  // Data ranges over the finite samples (and the marker, so that it is always visible).
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double x_lo = kInf, x_hi = -kInf, y_lo = kInf, y_hi = -kInf;
  for (size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) continue;
    x_lo = std::min(x_lo, x[i]);
    x_hi = std::max(x_hi, x[i]);
    y_lo = std::min(y_lo, y[i]);
    y_hi = std::max(y_hi, y[i]);
  }
  if (options.marker_x && std::isfinite(*options.marker_x)) {
    x_lo = std::min(x_lo, *options.marker_x);
    x_hi = std::max(x_hi, *options.marker_x);
  }
  if (!(x_lo <= x_hi)) x_lo = 0.0, x_hi = 1.0;
  if (!(y_lo <= y_hi)) y_lo = 0.0, y_hi = 1.0;
  if (x_hi - x_lo <= 1e-12 * std::max(1.0, std::abs(x_lo))) x_lo -= 1.0, x_hi += 1.0;
  if (y_hi - y_lo <= 1e-12 * std::max(1.0, std::abs(y_lo))) {
    y_lo -= 1.0, y_hi += 1.0;
  } else {
    const double pad = 0.05 * (y_hi - y_lo);
    y_lo -= pad, y_hi += pad;
  }

  LinePlot plot;
  plot.image = Image(options.width, options.height, 1.0f);
  Canvas canvas(plot.image);
  LinePlotFrame& f = plot.frame;
  const double x_step = NiceStep(x_lo, x_hi, 6), y_step = NiceStep(y_lo, y_hi, 5);
  const std::vector<double> x_ticks = Ticks(x_lo, x_hi, x_step), y_ticks = Ticks(y_lo, y_hi, y_step);
  // Room on the left for the widest y label.
  int label_width = 0;
  if (options.tick_labels)
    for (double t : y_ticks) label_width = std::max(label_width, TextWidth(TickLabel(t, y_step)));
  f.left = std::min(options.width / 2, (options.tick_labels ? label_width + 10 : 6) + 1);
  f.top = 9;
  f.right = options.width - 14;
  f.bottom = options.height - (options.tick_labels ? 22 : 7);
  f.x_min = x_lo, f.x_max = x_hi, f.y_min = y_lo, f.y_max = y_hi;

  // Grid lines and ticks, then the axes box (one pixel outside the plot area).
  for (double t : x_ticks) {
    const int px = std::clamp(int(std::floor(f.PixelX(t))), f.left, f.right);
    canvas.VLine(px, f.top, f.bottom, kGrid);
    canvas.VLine(px, f.bottom + 1, f.bottom + 4, kAxes);
    if (options.tick_labels) {
      const std::string label = TickLabel(t, x_step);
      canvas.Text(px - TextWidth(label) / 2, f.bottom + 7, label, kAxes);
    }
  }
  for (double t : y_ticks) {
    const int py = std::clamp(int(std::floor(f.PixelY(t))), f.top, f.bottom);
    canvas.HLine(f.left, f.right, py, kGrid);
    canvas.HLine(f.left - 4, f.left - 1, py, kAxes);
    if (options.tick_labels) {
      const std::string label = TickLabel(t, y_step);
      canvas.Text(f.left - 6 - TextWidth(label), py - 3, label, kAxes);
    }
  }
  canvas.HLine(f.left - 1, f.right + 1, f.top - 1, kAxes);
  canvas.HLine(f.left - 1, f.right + 1, f.bottom + 1, kAxes);
  canvas.VLine(f.left - 1, f.top - 1, f.bottom + 1, kAxes);
  canvas.VLine(f.right + 1, f.top - 1, f.bottom + 1, kAxes);

  if (options.marker_x && std::isfinite(*options.marker_x)) {
    const int px = std::clamp(int(std::floor(f.PixelX(*options.marker_x))), f.left, f.right);
    for (int dx = 0; dx < 2; ++dx) canvas.VLine(std::min(px + dx, f.right), f.top, f.bottom, options.marker_colour);
  }

  // The polyline on top; a non-finite sample ends one run and the next finite one starts another.
  bool have_previous = false;
  double px0 = 0, py0 = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) {
      have_previous = false;
      continue;
    }
    const double px = f.PixelX(x[i]), py = f.PixelY(y[i]);
    if (have_previous) Segment(canvas, f, px0, py0, px, py, options.line_colour);
    if (options.points) Dot(canvas, f, px, py, 2.6, options.line_colour);
    px0 = px, py0 = py, have_previous = true;
  }
  return plot;
}

}  // namespace vkr
