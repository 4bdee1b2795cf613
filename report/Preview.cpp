#include "report/Preview.h"

#include <algorithm>
#include <array>
#include <fstream>
#include <set>
#include <sstream>

#include "engine/common/InputError.h"
#include "engine/geometry/SceneGeometry.h"
#include "engine/scene/Photographs.h"
#include "pipelines/rendering/WireframeOverlay.h"
#include "report/PreviewData.h"
#include "report/ReportAssets.h"
// The page's own style and script, embedded at build time (report/CMakeLists.txt).
#include "embedded/error_hook_js.h"
#include "embedded/expression_js.h"
#include "embedded/preview_css.h"
#include "embedded/preview_js.h"
#include "embedded/preview_ui_js.h"

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace vkr::report {
namespace {

// The page's photographs share this budget; past it their side halves (as the report's do).
constexpr size_t kPreviewImageBudget = 6 * 1024 * 1024;
// The prior's extremes, faint under the starting values' bright lines.
constexpr WireframeOptions kExtremeLines = {20.0, {0.35f, 0.85f, 1.0f}, 0.45f};

// Ψ with one parameter moved to each end of its slider: the faint wireframes of the PNGs.
std::vector<std::vector<double>> Extremes(const Scene& scene, const std::vector<double>& psi) {
  std::vector<std::vector<double>> out;
  for (size_t p = 0; p < scene.parameters.size(); ++p) {
    const auto [lo, hi] = SliderRange(scene.parameters[p]);
    for (double end : {lo, hi}) {
      if (end == psi[p]) continue;
      out.push_back(psi);
      out.back()[p] = end;
    }
  }
  return out;
}

std::vector<fs::path> WriteOverlays(const fs::path& dir, const Scene& scene, const SceneGeometry& geometry,
                                    const std::vector<double>& psi) {
  fs::create_directories(dir);
  const std::vector<WireEdge> bright = SceneEdges(scene, geometry, psi);
  // Edges a parameter does not move (the ground under a box) would be drawn once per extreme,
  // each faint line over the last until they are solid: each edge is drawn once.
  std::set<std::array<double, 6>> seen;
  auto first_time = [&](const WireEdge& e) {
    return seen.insert({e.a.x(), e.a.y(), e.a.z(), e.b.x(), e.b.y(), e.b.z()}).second;
  };
  for (const WireEdge& e : bright) first_time(e);
  std::vector<WireEdge> faint;
  for (const std::vector<double>& extreme : Extremes(scene, psi))
    for (WireEdge& e : SceneEdges(scene, geometry, extreme))
      if (first_time(e)) faint.push_back(std::move(e));
  std::vector<fs::path> written;
  const std::vector<WorldTriangle> triangles = SceneTriangles(scene, geometry, psi);
  // The cameras at Ψ throughout: a camera moved by a pose is drawn where it starts. The model
  // at Ψ hides its own edges; the extremes' are drawn whole (another shape hides them).
  for (const Camera& camera : scene.Cameras(psi)) {
    const fs::path file = dir / (camera.name + ".png");
    const Image faint_drawn = DrawWireframe(LoadPhotograph(camera.image, camera.shrink), camera, faint, kExtremeLines);
    const DepthBuffer hidden(camera, triangles);
    WritePng(file, DrawWireframe(faint_drawn, camera, bright, {}, &hidden));
    written.push_back(file);
  }
  return written;
}

// One <figure> per camera: the photograph under an SVG in its pixel coordinates, whose two
// paths (the extremes and the current values) preview.js draws.
std::string Figures(const Scene& scene, int side) {
  std::ostringstream h;
  for (size_t c = 0; c < scene.cameras.size(); ++c) {
    const CameraModel& camera = scene.cameras[c];
    const std::optional<std::string> uri = ImageDataUri(camera.image, side);
    h << "<figure class=\"camera\"><svg id=\"camera-" << c << "\" viewBox=\"0 0 " << camera.width << ' '
      << camera.height << "\">";
    if (uri)
      h << "<image href=\"" << *uri << "\" width=\"" << camera.width << "\" height=\"" << camera.height
        << "\" preserveAspectRatio=\"none\"/>";
    h << "<path class=\"extreme\" d=\"\"/><path class=\"current\" d=\"\"/></svg><figcaption>" << Html(camera.name)
      << (uri ? "" : " (the photograph could not be read)") << "</figcaption></figure>\n";
  }
  return h.str();
}

// The scene file as written, for the page's "save scene" button; null when it is not plain JSON.
Json SceneFileJson(const fs::path& file) {
  std::ifstream in(file);
  try {
    return Json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return nullptr;
  }
}

std::string Page(const Scene& scene, const Json& data, const std::string& figures) {
  std::string data_text = data.dump();
  // Inside <script>, only "</" could end the element early; "<\/" means the same to JSON.parse.
  for (size_t at = 0; (at = data_text.find("</", at)) != std::string::npos;) data_text.replace(at, 2, "<\\/"), at += 3;
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>vkrecon preview: "
    << Html(scene.file.parent_path().filename().string()) << "</title>\n<script>\n"
    << kErrorHookJs << "</script>\n<style>\n" << kPreviewCss << "</style>\n</head><body>\n"
    << "<h1>vkrecon preview</h1>\n<p class=\"meta\">scene " << Html(scene.file.string())
    << ". Yellow: the scene's wireframe at the sliders' values; faint blue: each parameter moved to either end "
       "of its range, the others at the sliders' values (a uniform prior's bounds, a normal's mean ± 3 sd). The page "
       "recomputes the scene exactly (transforms, expressions, lens) as vkrecon does; hidden edges are drawn "
       "too. docs/guide/REAL_PHOTOS.md.</p>\n<ul id=\"report-errors\"></ul>\n"
    << "<div id=\"controls\"><div id=\"sliders\"></div>\n<p><button id=\"save-at\">save values (--at JSON)</button> "
       "<button id=\"save-scene\">save scene with these as init</button> <button id=\"reset\">reset</button></p>\n"
       "<pre id=\"at-json\"></pre><pre id=\"scene-json\"></pre></div>\n<div id=\"cameras\">\n"
    << figures << "</div>\n<script type=\"application/json\" id=\"preview-data\">" << data_text
    << "</script>\n<script>\n" << kExpressionJs << kPreviewJs << kPreviewUiJs << "</script>\n</body></html>\n";
  return h.str();
}

void WriteText(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  if (!out) throw InputError(file.string(), "", "cannot write");
}

}  // namespace

std::pair<double, double> SliderRange(const Parameter& parameter) {
  const Prior& prior = parameter.prior;
  double lo = prior.kind == Prior::Kind::Uniform ? prior.a : prior.a - 3.0 * prior.b;
  double hi = prior.kind == Prior::Kind::Uniform ? prior.b : prior.a + 3.0 * prior.b;
  if (parameter.bounds) lo = std::max(lo, parameter.bounds->first), hi = std::min(hi, parameter.bounds->second);
  return {lo, hi};
}

PreviewResult WritePreview(const PreviewOptions& options) {
  const Scene scene = LoadScene(options.scene_file, options.overrides);
  const std::vector<double> psi =
      options.at_file.empty() ? scene.InitialValues() : scene.ValuesFromFile(options.at_file);
  SceneGeometry geometry;
  geometry.meshes = BuildMeshes(scene);
  const fs::path& out = options.output_dir;
  fs::create_directories(out);

  PreviewResult result;
  result.overlays = WriteOverlays(out / "overlays", scene, geometry, psi);
  Json data = PreviewData(scene, geometry.meshes, psi);
  data["scene_name"] = scene.file.filename().string();
  data["scene_json"] = SceneFileJson(scene.file);
  std::string figures;
  for (result.page_side = options.max_side;; result.page_side /= 2) {
    figures = Figures(scene, result.page_side);
    if (figures.size() <= kPreviewImageBudget || result.page_side <= 160) break;
  }
  const std::string html = Page(scene, data, figures);
  result.page = out / "preview.html";
  WriteText(result.page, html);
  result.page_bytes = html.size();

  scene.WriteValues(out / "at.json", psi);
  Json settings = {{"scene", fs::absolute(options.scene_file).string()},
                   {"at", options.at_file.empty() ? "" : fs::absolute(options.at_file).string()},
                   {"overrides", Json::array()}};
  for (const SceneOverride& o : options.overrides) settings["overrides"].push_back(o.path + "=" + o.value);
  WriteText(out / "preview.json", settings.dump(2) + "\n");
  return result;
}

std::string PreviewResult::BriefReport() const {
  std::ostringstream out;
  out << "vkrecon preview: " << overlays.size() << " overlays in "
      << (overlays.empty() ? std::string("-") : overlays.front().parent_path().string()) << "; " << page.string() << " ("
      << (page_bytes + 512) / 1024 << " KiB, photographs at most " << page_side << " px)\n";
  return out.str();
}

}  // namespace vkr::report
