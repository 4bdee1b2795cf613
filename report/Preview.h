#pragma once
// `vkrecon preview`: a scene checked against its photographs before a run
// (docs/guide/REAL_PHOTOS.md, "Check it before a run"). Per camera a PNG with the scene's wireframe at the
// starting values over the photograph, and faintly at each parameter's extremes; and one
// offline page, preview.html, whose sliders move the wireframe on every photograph live. The
// page recomputes the scene exactly (the transform graph, the expressions, the lens) in
// JavaScript (report/preview.js), and checks its port against the C++ values when it loads.

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "engine/scene/Scene.h"

namespace vkr::report {

struct PreviewOptions {
  std::filesystem::path scene_file;
  std::vector<SceneOverride> overrides;  // --set
  // An `--at` file of values to draw at; empty: the scene's `init` (else the prior's centre).
  std::filesystem::path at_file;
  std::filesystem::path output_dir;
  // The page's photographs are JPEG copies, their longest side at most this (pixels), halved
  // until the page fits its budget; the PNGs keep the photographs' size.
  int max_side = 1280;
};

struct PreviewResult {
  std::vector<std::filesystem::path> overlays;  // OUT/overlays/<camera>.png
  std::filesystem::path page;                   // OUT/preview.html
  std::uintmax_t page_bytes = 0;
  int page_side = 0;  // the longest side of the page's photographs
  std::string BriefReport() const;
};

// A parameter's slider range: a uniform prior's support, a normal's mean ± 3 sd, either cut
// to the parameter's bounds. The PNGs' faint wireframes are drawn at its two ends.
std::pair<double, double> SliderRange(const Parameter& parameter);

// Loads the scene (its photographs must exist) and writes OUT/overlays/, OUT/preview.html,
// OUT/at.json (the values drawn) and OUT/preview.json (the settings, to repeat it). Throws
// InputError for a bad scene, a missing photograph or a bad --at file.
PreviewResult WritePreview(const PreviewOptions& options);

}  // namespace vkr::report
