#include "report/Report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "report/ReportAssets.h"
// The page's own style and scripts, embedded from report/*.css and *.js at build time
// (report/CMakeLists.txt).
#include "embedded/error_hook_js.h"
#include "embedded/model_view_js.h"
#include "embedded/page_css.h"
#include "embedded/page_js.h"
#include "engine/common/InputError.h"
#include "pipelines/rendering/WireframeOverlay.h"

#ifndef VKRECON_JAVASCRIPT_DIR
#define VKRECON_JAVASCRIPT_DIR "/usr/share/javascript"
#endif

namespace fs = std::filesystem;
using nlohmann::json;

namespace vkr::report {
namespace {

// The page stays under 5 MB: the libraries take about 1.2 MB, model.glb at most this much,
// and the images what is left of their budget (ImageDataUri halves their size until they fit).
constexpr std::uintmax_t kModelBudget = 1500 * 1024;
constexpr size_t kImageBudget = 2200 * 1024;

// The libraries, by package: Chart.js draws the plots, three.js (with its glTF loader and
// orbit controls) the 3D view.
struct Library {
  const char* package;
  const char* file;  // relative to the JavaScript directory
};
constexpr Library kChart = {"libjs-chart.js", "chart.js/chart.min.js"};
constexpr Library kThree[] = {{"libjs-three", "three/three.min.js"},
                              {"libjs-three", "three/examples/js/loaders/GLTFLoader.js"},
                              {"libjs-three", "three/examples/js/controls/OrbitControls.js"}};

json ReadJson(const fs::path& file, const char* if_missing) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string(), "", std::string("missing or unreadable: ") + if_missing);
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw InputError(file.string(), "", std::string("not valid JSON: ") + e.what());
  }
}

std::string Number(const json& v, const char* format = "%.4g") {
  if (!v.is_number()) return "–";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v.get<double>());
  return buf;
}

// The scene the run read (map.json's settings), for the priors and the cameras' order; null
// when it cannot be read now (moved, edited): the page then says so and shows no priors.
std::unique_ptr<Scene> RunScene(const json& map, std::string* why) {
  try {
    const json& settings = map.at("settings");
    std::vector<std::string> sets;
    for (const auto& o : settings.value("overrides", json::array())) sets.push_back(o.get<std::string>());
    LoadOptions load;
    load.require_images = false;
    return std::make_unique<Scene>(LoadScene(settings.at("scene").get<std::string>(), ParseOverrides(sets), load));
  } catch (const std::exception& e) {
    *why = e.what();
    return nullptr;
  }
}

std::string PriorText(const Prior& p) {
  char buf[96];
  if (p.kind == Prior::Kind::Uniform) std::snprintf(buf, sizeof buf, "uniform [%g, %g]", p.a, p.b);
  else std::snprintf(buf, sizeof buf, "normal (%g, %g)", p.a, p.b);
  return buf;
}

// The parameter table; also fills the plots' per-parameter data.
std::string ParameterTable(const json& map, const std::vector<std::string>& names, const Scene* scene, const json& truth,
                           json* plot) {
  std::ostringstream h;
  const bool has_truth = truth.is_object();
  h << "<table class=\"params\"><tr><th>parameter</th><th>prior</th><th>MAP</th><th>mean ± sd</th>"
       "<th>95 % interval</th><th>R̂</th><th>ESS</th>"
    << (has_truth ? "<th>truth</th>" : "") << "</tr>\n";
  // The scene's order (chain.csv's columns); map.json's object is sorted by name.
  std::vector<std::string> order = names;
  for (const auto& [name, p] : map.at("parameters").items())
    if (std::find(order.begin(), order.end(), name) == order.end()) order.push_back(name);
  for (const std::string& name : order) {
    if (!map["parameters"].contains(name)) continue;
    const json& p = map["parameters"][name];
    if (!p.is_object()) continue;
    json entry = {{"name", name}, {"map", p.value("map", json())}, {"q025", p.value("q025", json())},
                  {"q975", p.value("q975", json())}, {"shift", p.value("interval_shift", json(0.0))},
                  {"prior", nullptr}, {"truth", nullptr}};
    std::string prior = "–";
    const int index = scene ? scene->ParameterIndex(name) : -1;
    if (index >= 0) {
      const Prior& pr = scene->parameters[size_t(index)].prior;
      prior = PriorText(pr);
      entry["prior"] = {{"kind", pr.kind == Prior::Kind::Uniform ? "uniform" : "normal"}, {"a", pr.a}, {"b", pr.b}};
    }
    const json rhat = p.value("rhat", json()), ess = p.value("ess", json());
    const bool bad_rhat = rhat.is_number() && rhat.get<double>() > 1.1;
    const bool low_ess = ess.is_number() && ess.get<double>() < 400.0;
    h << "<tr><td class=\"name\">" << Html(name) << "</td><td>" << Html(prior) << "</td><td>" << Number(p.value("map", json()))
      << "</td><td>" << Number(p.value("mean", json())) << " ± " << Number(p.value("sd", json()), "%.2g") << "</td><td>[" << Number(p.value("q025", json()))
      << ", " << Number(p.value("q975", json())) << "]</td><td" << (bad_rhat ? " class=\"warn\" title=\"R̂ &gt; 1.1: the chains disagree\"" : "")
      << ">" << Number(rhat, "%.3f") << "</td><td" << (low_ess ? " class=\"warn\" title=\"ESS &lt; 400: few independent draws\"" : "")
      << ">" << Number(ess, "%.0f") << "</td>";
    if (has_truth) {
      const json t = truth.value(name, json());
      entry["truth"] = t;
      const bool miss = t.is_number() && p.value("q025", json()).is_number() && p.value("q975", json()).is_number() &&
                        (t.get<double>() < p.value("q025", json()).get<double>() || t.get<double>() > p.value("q975", json()).get<double>());
      h << "<td" << (miss ? " class=\"miss\" title=\"the truth lies outside the 95 % interval\"" : "") << ">"
        << Number(t) << "</td>";
    }
    h << "</tr>\n";
    plot->push_back(std::move(entry));
  }
  h << "</table>\n<p class=\"legend\"><span class=\"warn\">amber</span>: R̂ &gt; 1.1 (the chains disagree) or ESS "
       "&lt; 400 (few independent draws)"
    << (has_truth ? "; <span class=\"miss\">red</span>: the truth lies outside the 95 % interval" : "") << ".</p>\n";
  return h.str();
}

std::string Calibration(const json& map) {
  const json c = map.value("calibration", json());
  const json d = map.value("diagnosis", json());
  std::ostringstream h;
  h << "<table class=\"kv\">";
  auto row = [&](const std::string& key, const std::string& value, const std::string& why) {
    h << "<tr><th>" << key << "</th><td>" << value << "</td><td class=\"why\">" << why << "</td></tr>";
  };
  if (c.is_object()) {
    row("σ", Number(c.value("sigma", json())) + (c.value("sigma_estimated", false) ? " (estimated)" : " (given)"),
        "noise sd, 0–255 scale");
    row("δ", Number(c.value("position_sd", json())), "position noise, pixels");
    const json block = c.value("block", json());
    row("κ", Number(c.value("kappa", json())),
        "sandwich factor: the likelihood is divided by it" +
            (block.is_number() ? " (over blocks of " + Number(block) + "×" + Number(block) + " texels)" : std::string()));
    row("κ<sub>min</sub> / κ<sub>max</sub>",
        Number(c.value("kappa_min", json())) + " / " + Number(c.value("kappa_max", json())),
        "the sandwich's eigenvalues (κ<sub>min</sub> &lt; 1: the curvature is doubtful)");
    const json intervals = c.value("intervals", json());
    if (intervals.is_object()) {
      const std::string from = intervals.value("from", std::string());
      row("intervals at κ", Number(intervals.value("kappa", json())),
          from == "noise" ? "the noise's: the chains' spread about the MAP times " + Number(intervals.value("scale", json()))
          : from == "sandwich" ? "the sandwich's: " + Html(intervals.value("why", std::string()))
                               : "as the chains sampled (" + Html(from) + ")");
    }
  } else {
    row("calibration", "none", "the run did not settle at a mode");
  }
  if (d.is_object()) {
    row("χ²/dof", Number(d.value("chi2_per_dof", json())), "at the MAP");
    row("reprojection RMS", Number(d.value("reprojection_rms", json())), "0–255 scale, pixels the model covers");
    row("outlier share", Number(d.value("outlier_share", json())), "of the view samples");
  }
  h << "</table>\n";
  return h.str();
}

std::string Verdict(const json& map) {
  const json d = map.value("diagnosis", json());
  std::ostringstream h;
  const std::string verdict = d.is_object() ? d.value("verdict", std::string("unknown")) : "unknown";
  h << "<p class=\"verdict " << (d.is_object() && d.value("ok", false) ? "ok" : "bad") << "\">diagnosis: <b>" << Html(verdict)
    << "</b></p>\n";
  if (d.is_object() && !d.value("notes", json::array()).empty()) {
    h << "<ul class=\"notes\">";
    for (const auto& n : d["notes"]) h << "<li>" << Html(n.get<std::string>()) << "</li>";
    h << "</ul>\n";
  }
  h << "<p>sampler: " << Html(map.value("termination", std::string("?")));
  if (map.contains("sampling") && map["sampling"].is_object() && map["sampling"].contains("ended_by"))
    h << "; sampling ended by <b>"
      << Html(map["sampling"]["ended_by"].is_string() ? map["sampling"]["ended_by"].get<std::string>()
                                                       : map["sampling"]["ended_by"].dump())
      << "</b>";
  h << "; " << Number(map.value("iterations", json()), "%.0f") << " iterations (burn-in "
    << Number(map.value("burn_in", json()), "%.0f") << "), " << Number(map.value("evaluations", json()), "%.0f")
    << " likelihood evaluations; log posterior at the MAP " << Number(map.value("log_posterior", json()), "%.6g")
    << ".</p>\n";
  return h.str();
}

// Camera names: the scene's order when it could be read, else the overlays and reprojections found.
std::vector<std::string> CameraNames(const fs::path& out, const Scene* scene) {
  std::vector<std::string> names;
  if (scene) {
    for (const CameraModel& c : scene->cameras) names.push_back(c.name);
    return names;
  }
  if (fs::is_directory(out / "reprojections"))
    for (const auto& e : fs::directory_iterator(out / "reprojections")) {
      const std::string stem = e.path().stem().string();
      if (e.path().extension() == ".png" && !stem.ends_with("_residual")) names.push_back(stem);
    }
  std::sort(names.begin(), names.end());
  return names;
}

std::string Figure(const std::optional<std::string>& uri, const std::string& caption, const std::string& missing,
                   const char* kind = "") {
  if (!uri) return "<figure class=\"missing\"><figcaption>" + Html(missing) + "</figcaption></figure>";
  return std::string("<figure class=\"") + kind + "\"><img src=\"" + *uri + "\" alt=\"" + Html(caption) + "\"><figcaption>" + Html(caption) +
         "</figcaption></figure>";
}

// The cameras and the composite, with the images scaled until they fit the budget.
std::string Images(const fs::path& out, const std::vector<std::string>& cameras, const json& map) {
  json per_camera = json::object();
  if (map.contains("diagnosis") && map["diagnosis"].contains("cameras"))
    for (const auto& c : map["diagnosis"]["cameras"]) per_camera[c.value("camera", std::string())] = c;
  for (int side = 640;; side /= 2) {
    std::ostringstream h;
    for (const std::string& name : cameras) {
      h << "<section class=\"camera\"><h3>" << Html(name) << "</h3>";
      if (per_camera.contains(name)) {
        const json& c = per_camera[name];
        h << "<p>RMS " << Number(c.value("rms_255", json()), "%.2f") << " (0–255) over "
          << Number(c.value("pixels", json()), "%.0f") << " pixels; outliers "
          << Number(c.value("outlier_share", json()), "%.3f") << "; clutter " << Number(c.value("clutter_share", json()), "%.3f")
          << (c.value("disagrees", false) ? " — <span class=\"warn\">disagrees</span>" : "") << "</p>";
      }
      h << "<div class=\"row\">"
        << Figure(report::ImageDataUri(out / "overlays" / (name + ".png"), side), "photograph with the fitted wireframe",
                  "overlays/" + name + ".png is missing")
        << Figure(report::ImageDataUri(out / "reprojections" / (name + "_residual.png"), side),
                  "residual χ² (blue 0, green 1, yellow 2, red ≥ 4)", "reprojections/" + name + "_residual.png is missing")
        << "</div><div class=\"row\">"
        << Figure(report::ImageDataUri(out / "reprojections" / (name + ".png"), 2 * side),
                  "photograph | model | |difference| × 4", "reprojections/" + name + ".png is missing", "wide")
        << "</div></section>\n";
    }
    h << "<h2 id=\"composite\">Composite texture</h2>"
      << Figure(report::ImageDataUri(out / "composite.png", std::max(side, 256)),
                "composite.png: the model's texture atlas, one chart per face", "composite.png is missing");
    if (h.str().size() <= kImageBudget || side <= 80) return h.str();
  }
}

ReportResult WritePage(const ReportOptions& options);

}  // namespace

fs::path JavascriptDir(const ReportOptions& options) {
  if (!options.javascript_dir.empty()) return options.javascript_dir;
  if (const char* env = std::getenv("VKRECON_JAVASCRIPT_DIR"); env && *env) return env;
  return VKRECON_JAVASCRIPT_DIR;
}

ReportResult WriteReport(const ReportOptions& options) {
  try {
    return WritePage(options);
  } catch (const json::exception& e) {  // a field of the wrong type: the files are not a run's
    throw InputError((options.output_dir / "map.json").string(), "", std::string("unexpected content: ") + e.what());
  }
}

namespace {

ReportResult WritePage(const ReportOptions& options) {
  const fs::path& out = options.output_dir;
  const json map = ReadJson(out / "map.json", "not the output folder of a finished run");
  if (!map.is_object() || !map.contains("parameters") || !map["parameters"].is_object())
    throw InputError((out / "map.json").string(), "parameters", "missing: not a run's map.json");
  json chain = report::ReadChain(out / "chain.csv");
  json truth;
  if (!options.truth_file.empty()) truth = ReadJson(options.truth_file, "the --truth file");
  if (!truth.is_null() && !truth.is_object())
    throw InputError(options.truth_file.string(), "", "not an --at file ({\"name\": value, ...})");
  std::string scene_problem;
  const std::unique_ptr<Scene> scene = RunScene(map, &scene_problem);

  ReportResult result;
  result.file = out / "report.html";
  const fs::path js = JavascriptDir(options);
  const std::optional<std::string> chart_js = report::ReadLibrary(js / kChart.file);
  std::string three_js;
  bool has_three = true;
  for (const Library& l : kThree) {
    const auto text = report::ReadLibrary(js / l.file);
    has_three = has_three && text.has_value();
    if (text) three_js += *text + "\n";
  }
  if (!chart_js)
    result.left_out.push_back("the plots (" + (js / kChart.file).string() + " is missing: install Debian's " +
                              kChart.package + ")");
  const bool has_model = fs::is_regular_file(out / "model.glb");
  const bool model_fits = has_model && fs::file_size(out / "model.glb") <= kModelBudget;
  if (!has_three)
    result.left_out.push_back("the 3D view (three.js, its GLTFLoader or OrbitControls under " + js.string() +
                              " is missing: install Debian's libjs-three)");

  const json settings = map.value("settings", json::object());
  json data = {{"parameters", json::array()}, {"burn_in", map.value("burn_in", 0)}, {"chain", std::move(chain)},
               {"ladder", map.value("chains", json::array())}};
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
       "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>vkrecon report: "
    << Html(fs::path(settings.value("scene", std::string("run"))).parent_path().filename().string())
    << "</title>\n<script>\n" << kErrorHookJs << "</script>\n<style>\n" << kPageCss << "</style>\n</head><body>\n"
    << "<h1>vkrecon report</h1>\n<p class=\"meta\">scene " << Html(settings.value("scene", std::string("?")))
    << "; device " << Html(settings.value("device", std::string("?"))) << "; built from the files in this folder by "
    << "<code>vkrecon report</code> (docs/guide/REPORT.md).</p>\n<ul id=\"report-errors\"></ul>\n";
  if (!result.left_out.empty() || (has_model && !model_fits) || !scene) {
    h << "<div class=\"leftout\"><p>Left out of this page:</p><ul>";
    for (const std::string& l : result.left_out) h << "<li>" << Html(l) << "</li>";
    if (has_model && !model_fits)
      h << "<li>the 3D view: model.glb is " << fs::file_size(out / "model.glb") / 1024
        << " KiB, over the page's budget (open it in Blender: File › Import › glTF 2.0)</li>";
    if (!scene) h << "<li>the priors and the cameras' order (the scene cannot be read now: " << Html(scene_problem) << ")</li>";
    h << "</ul></div>\n";
  }
  h << "<nav><a href=\"#summary\">summary</a> · <a href=\"#parameters\">parameters</a> · <a href=\"#sampler\">sampler</a> · "
       "<a href=\"#marginals\">traces and marginals</a> · <a href=\"#cameras\">cameras</a> · <a href=\"#composite\">texture</a> · "
       "<a href=\"#model\">3D model</a></nav>\n";
  h << "<h2 id=\"summary\">Diagnosis</h2>\n" << Verdict(map);
  h << "<h2 id=\"parameters\">Parameters</h2>\n" << ParameterTable(map, data["chain"]["names"].get<std::vector<std::string>>(), scene.get(), truth,
                                                        &data["parameters"]);
  h << "<h2 id=\"calibration\">Calibration</h2>\n" << Calibration(map);
  const char* no_charts = "<p class=\"nochart\">(plot left out: Chart.js is not installed)</p>";
  h << "<h2 id=\"sampler\">Sampler</h2>\n<p>Chains' coldest replicas from chain.csv; the dashed line marks the end of "
       "the burn-in. Rates are shares per iteration, averaged over a sliding window.</p>\n<div class=\"grid\">"
    << "<div class=\"chart\"><canvas id=\"chart-logpost\"></canvas></div><div class=\"chart\"><canvas id=\"chart-rates\">"
       "</canvas></div><div class=\"chart\"><canvas id=\"chart-temperature\"></canvas></div><div class=\"chart\"><canvas "
       "id=\"chart-ladder\"></canvas></div></div>\n"
    << (chart_js ? "" : no_charts);
  // Whether the intervals moved with a MAP polished at the finer atlas (ParameterTable's "shift").
  const bool moved = std::any_of(data["parameters"].begin(), data["parameters"].end(), [](const json& entry) {
    return entry["shift"].is_number() && entry["shift"].get<double>() != 0.0;
  });
  h << "<h2 id=\"marginals\">Traces and marginals</h2>\n<p>Left: each chain's trace. Right: the histogram of the draws "
       "after burn-in, all chains, with the prior's density (dashed) on the same scale and the MAP (red)"
    << (truth.is_object() ? " and the truth (green)" : "") << "."
    << (moved ? " The MAP was polished at twice the atlas's side after sampling, so the histograms, like map.json's "
                "intervals, show the draws moved with it (<code>interval_shift</code>); the traces show them as sampled."
              : "")
    << "</p>\n<div id=\"per-parameter\"></div>\n"
    << "<h3>Most correlated pairs</h3><div class=\"grid\" id=\"pairs\"></div>\n" << (chart_js ? "" : no_charts);
  h << "<h2 id=\"cameras\">Cameras</h2>\n<p>The wireframe is the model at the MAP: its boundary edges, its creases "
       "(faces turning by more than 20°) and its silhouette; hidden edges are drawn too. Images are JPEG copies, "
       "scaled to keep the page small; the originals are in overlays/ and reprojections/.</p>\n"
    << Images(out, CameraNames(out, scene.get()), map);
  h << "<h2 id=\"model\">3D model</h2>\n";
  if (has_three && model_fits) {
    std::ifstream glb(out / "model.glb", std::ios::binary);
    std::ostringstream bytes;
    bytes << glb.rdbuf();
    h << "<p>model.glb (drag to turn, scroll to zoom).</p><div id=\"model-view\"></div>\n"
      << "<script type=\"application/octet-stream\" id=\"model-glb\">" << report::Base64(bytes.str()) << "</script>\n";
  } else if (!has_model) {
    h << "<p>model.glb is missing.</p>\n";
  } else {
    h << "<p>The 3D view is left out (see the top of the page); model.glb opens in Blender (File › Import › glTF 2.0).</p>\n";
  }
  std::string data_text = data.dump();
  for (size_t at = 0; (at = data_text.find("</", at)) != std::string::npos;) data_text.replace(at, 2, "<\\/"), at += 3;
  h << "<script type=\"application/json\" id=\"report-data\">" << data_text << "</script>\n";
  if (chart_js) h << "<script>" << *chart_js << "</script>\n<script>\n" << kPageJs << "</script>\n";
  if (has_three && model_fits) h << "<script>" << three_js << "</script>\n<script>\n" << kModelViewJs << "</script>\n";
  h << "</body></html>\n";

  const std::string html = h.str();
  const fs::path tmp = out / "report.html.tmp";
  {
    std::ofstream file(tmp, std::ios::binary);
    file << html;
    if (!file) throw InputError(tmp.string(), "", "cannot write");
  }
  fs::rename(tmp, result.file);
  result.bytes = html.size();
  return result;
}

}  // namespace

void WriteRunReport(const fs::path& output_dir, const Scene& scene, const SceneGeometry& geometry,
                    const std::vector<double>& psi) {
  WriteWireframeOverlays(output_dir / "overlays", scene, geometry, psi);
  const ReportResult report = WriteReport({output_dir, {}, {}});
  if (!report.left_out.empty()) {
    std::string parts;
    for (const std::string& l : report.left_out) parts += (parts.empty() ? "" : "; ") + l;
    std::cerr << "vkrecon run: warning: " << report.file.string() << " lacks " << parts << "\n";
  }
}

}  // namespace vkr::report
