#include <iostream>

#include "apps/Commands.h"
#include "report/Report.h"

namespace vkr::app {

int RunReport(int argc, char** argv) {
  CLI::App app(
      "Write OUT/report.html again from the files of a finished run in OUT (map.json, chain.csv, "
      "overlays/, reprojections/, composite.png, model.glb), as `vkrecon run` does at its end: one "
      "self-contained page (no network) with the parameter table and its warnings (R-hat > 1.1, ESS < 400, "
      "with --truth the intervals that miss it), the calibration and diagnosis, the sampler's plots "
      "(Chart.js), each camera's photograph with the fitted wireframe, reprojection and residuals, the "
      "texture and a 3D view of the model (three.js). The libraries are read from Debian's libjs-chart.js "
      "and libjs-three (VKRECON_JAVASCRIPT_DIR, default /usr/share/javascript); without them the page keeps "
      "its tables and images and says what it left out. docs/guide/REPORT.md.",
      "report");
  report::ReportOptions options;
  std::string out, truth;
  bool quiet = false;
  app.add_option("output", out, "a run's output folder (the -o of vkrecon run)")->required();
  app.add_option("--truth", truth, "an --at file of true values: the table marks the 95 % intervals that miss them");
  app.add_flag("-q,--quiet", quiet, "no summary line");
  if (auto status = Parse(app, argc, argv)) return *status;
  options.output_dir = out;
  options.truth_file = truth;
  const report::ReportResult result = report::WriteReport(options);
  for (const std::string& l : result.left_out) std::cerr << "vkrecon report: warning: left out " << l << "\n";
  if (!quiet)
    std::cerr << "vkrecon report: wrote " << result.file.string() << " (" << (result.bytes + 512) / 1024 << " KiB)\n";
  return 0;
}

}  // namespace vkr::app
