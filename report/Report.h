#pragma once
// OUT/report.html: one self-contained page that shows a run (docs/guide/REPORT.md) — the parameter
// table with its warnings, the calibration and diagnosis, the sampler's traces, marginals,
// most correlated pair, acceptance and temperatures (Chart.js), per camera the photograph
// with the fitted wireframe, the reprojection and the residuals, the composite texture and
// a 3D view of model.glb (three.js). Built from the files in OUT alone, so `vkrecon report`
// rebuilds it byte for byte. docs/guide/REPORT.md describes the page and why it is built so.

#include <filesystem>
#include <string>
#include <vector>

#include "engine/geometry/SceneGeometry.h"
#include "engine/scene/Scene.h"

namespace vkr::report {

struct ReportOptions {
  std::filesystem::path output_dir;  // a run's OUT folder (map.json, chain.csv, …)
  // An `--at` file of true values (synthetic data): the table marks the intervals that miss
  // them. Empty: no truth column.
  std::filesystem::path truth_file;
  // Where Debian's libjs-chart.js and libjs-three put their files; empty: the environment's
  // VKRECON_JAVASCRIPT_DIR, else the build's default (/usr/share/javascript).
  std::filesystem::path javascript_dir;
};

struct ReportResult {
  std::filesystem::path file;  // OUT/report.html
  std::uintmax_t bytes = 0;
  // The interactive parts left out, each with why and which package provides them (the page
  // says the same); empty when the page is complete.
  std::vector<std::string> left_out;
};

// Writes OUT/report.html from OUT's files. Throws InputError naming OUT/map.json or
// OUT/chain.csv when one is missing or unreadable; images, model.glb and the JavaScript
// libraries are optional (the page says what it lacks).
ReportResult WriteReport(const ReportOptions& options);

// The end of `vkrecon run`, after map.json: OUT/overlays/<camera>.png (the photographs with
// the model at Ψ as a wireframe) and OUT/report.html; one warning line on stderr when the
// report lacks its interactive parts.
void WriteRunReport(const std::filesystem::path& output_dir, const Scene& scene, const SceneGeometry& geometry,
                    const std::vector<double>& psi);

// The library directory a report reads Chart.js and three.js from (see ReportOptions).
std::filesystem::path JavascriptDir(const ReportOptions& options);

}  // namespace vkr::report
