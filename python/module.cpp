// `import vkrecon`: scenes, the likelihood on a numpy batch, the `--at` format, a whole
// reconstruction and rendered views, through the same library calls the command line makes
// (docs/guide/PYTHON.md). The GIL is released while the GPU works; bad input raises
// vkrecon.InputError with the command line's one line.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "engine/common/InputError.h"
#include "pipelines/model/LikelihoodSettings.h"
#include "engine/geometry/SceneGeometry.h"
#include "engine/image/Image.h"
#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "pipelines/likelihood/LikelihoodTool.h"
#include "pipelines/rendering/ViewRendering.h"
#include "recon/Reconstruct.h"
#include "recon/SearchSetup.h"

namespace py = pybind11;

namespace {

// One Vulkan device for the whole process, opened on first use (the best one, as the
// command line picks it; VKRECON_DEVICE chooses another).
std::shared_ptr<vkr::vk::Device> SharedDevice() {
  static std::mutex mutex;
  static std::shared_ptr<vkr::vk::Device> device;
  std::lock_guard<std::mutex> lock(mutex);
  if (!device) device = std::make_shared<vkr::vk::Device>(vkr::vk::DeviceCreateInfo{});
  return device;
}

std::shared_ptr<vkr::Scene> LoadScene(const std::filesystem::path& file, const std::vector<std::string>& sets,
                                      bool require_images) {
  vkr::LoadOptions options;
  options.require_images = require_images;
  auto scene = std::make_shared<vkr::Scene>(vkr::LoadScene(file, vkr::ParseOverrides(sets), options));
  vkr::ResolveAutoLikelihood(*scene);  // as `vkrecon likelihood` and `run` do
  return scene;
}

std::vector<std::string> ParameterNames(const vkr::Scene& scene) {
  std::vector<std::string> names;
  for (const vkr::Parameter& p : scene.parameters) names.push_back(p.name);
  return names;
}

// A likelihood bound to its scene, which it reads while it lives.
struct PyLikelihood {
  std::shared_ptr<vkr::Scene> scene;
  std::shared_ptr<vkr::vk::Device> device;
  std::unique_ptr<vkr::Likelihood> likelihood;
};

std::vector<double> Row(const vkr::Scene& scene, py::array_t<double, py::array::c_style | py::array::forcecast> a) {
  if (a.ndim() != 1 || a.shape(0) != py::ssize_t(scene.parameters.size()))
    throw py::value_error("expected " + std::to_string(scene.parameters.size()) + " parameter values");
  return std::vector<double>(a.data(), a.data() + a.shape(0));
}

// K × P parameter values → one array of K per scalar the likelihood reduces to.
py::dict Evaluate(PyLikelihood& l, py::array_t<double, py::array::c_style | py::array::forcecast> batch) {
  const auto p = py::ssize_t(l.scene->parameters.size());
  if (batch.ndim() != 2 || batch.shape(1) != p)
    throw py::value_error("expected a K x " + std::to_string(p) + " array of parameter values");
  std::vector<std::vector<double>> rows(size_t(batch.shape(0)));
  for (size_t k = 0; k < rows.size(); ++k) rows[k].assign(batch.data(k, 0), batch.data(k, 0) + p);
  std::vector<vkr::Evaluation> out;
  {
    py::gil_scoped_release release;
    const size_t chunk = size_t(l.likelihood->max_batch());
    for (size_t first = 0; first < rows.size(); first += chunk) {
      const std::vector<std::vector<double>> part(rows.begin() + first, rows.begin() + std::min(rows.size(), first + chunk));
      for (const vkr::Evaluation& e : l.likelihood->Evaluate(part)) out.push_back(e);
    }
  }
  const auto column = [&](auto field) {
    py::array_t<double> a(py::ssize_t(out.size()));
    for (size_t k = 0; k < out.size(); ++k) a.mutable_at(k) = double(field(out[k]));
    return a;
  };
  py::dict d;
  d["total"] = column([](const vkr::Evaluation& e) { return e.total(); });
  d["log_likelihood"] = column([](const vkr::Evaluation& e) { return e.log_likelihood; });
  d["log_occlusion_prior"] = column([](const vkr::Evaluation& e) { return e.log_occlusion_prior; });
  d["log_edges"] = column([](const vkr::Evaluation& e) { return e.log_edges; });
  d["sum_squares"] = column([](const vkr::Evaluation& e) { return e.scalars.sum_squares; });
  d["dof"] = column([](const vkr::Evaluation& e) { return e.scalars.dof; });
  d["seen_multi"] = column([](const vkr::Evaluation& e) { return e.scalars.seen_multi; });
  d["seen_once"] = column([](const vkr::Evaluation& e) { return e.scalars.seen_once; });
  return d;
}

PyLikelihood MakeLikelihood(std::shared_ptr<vkr::Scene> scene, int batch, int level, bool chi2_correction) {
  if (batch < 1) throw py::value_error("batch must be at least 1");
  PyLikelihood l{std::move(scene), SharedDevice(), nullptr};
  vkr::LikelihoodSetup setup;
  setup.max_batch = batch;
  setup.chi2_correction = chi2_correction;
  l.likelihood = vkr::MakeLikelihood(*l.device, *l.scene, setup);
  if (level < 0 || level >= l.likelihood->levels())
    throw py::value_error("level must be in [0, " + std::to_string(l.likelihood->levels()) + ")");
  l.likelihood->SetLevel(level);
  return l;
}

// An image as an H × W × 4 float32 array (RGBA), copied.
py::array_t<float> ImageArray(const vkr::Image& image) {
  py::array_t<float> a(std::vector<py::ssize_t>{py::ssize_t(image.height), py::ssize_t(image.width), 4});
  std::copy(image.rgba.begin(), image.rgba.end(), a.mutable_data());
  return a;
}

// One camera of the scene at `at` (default: its initial values), as `vkrecon render --camera`
// renders it: textured by `texture` (a run's composite.exr) or the albedo baked into an atlas.
py::array_t<float> Render(const vkr::Scene& scene, std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>> at,
                          std::optional<std::string> camera, std::optional<std::filesystem::path> texture,
                          double scale, int atlas_side) {
  const std::vector<double> psi = at ? Row(scene, *at) : scene.InitialValues();
  if (scene.cameras.empty()) throw py::value_error("the scene has no camera");
  const std::string name = camera.value_or(scene.cameras.front().name);
  vkr::Image image;
  {
    py::gil_scoped_release release;
    std::vector<vkr::Camera> views;
    for (const vkr::Camera& c : scene.Cameras(psi))
      if (c.name == name) views.push_back(vkr::ScaleCamera(c, scale));
    if (views.empty()) throw vkr::InputError(scene.file.string(), "cameras", "no camera named '" + name + "'");
    vkr::Image atlas;
    if (texture) atlas = vkr::LoadImage(*texture);
    // The same layout as the run that made the texture: decided at the initial values.
    const vkr::SceneGeometry geometry =
        vkr::BuildSceneGeometry(scene, scene.InitialValues(), texture ? atlas.width : atlas_side,
                                vkr::LikelihoodSettingsOf(scene).charts);
    if (!texture) atlas = vkr::BakeAlbedoAtlas(geometry.atlas, geometry.meshes, vkr::LoadAlbedos(scene));
    image = vkr::RenderWithAtlas(*SharedDevice(), scene, psi, geometry, atlas, views).front();
  }
  return ImageArray(image);
}

// A run of `vkrecon run` on a loaded scene (its sampler block says how long). Ctrl-C
// checkpoints the run, then raises KeyboardInterrupt; `resume=True` continues it. `progress`
// (or None) is called with the evaluations so far and the running MAP after every sampler
// frame and wherever a search finds a better point; an exception it raises stops the run at
// its next checkpoint and is raised again.
vkr::recon::ReconstructSummary Reconstruct(std::shared_ptr<vkr::Scene> scene, const std::filesystem::path& output_dir,
                                           bool resume, double time_limit, int temperatures,
                                           double checkpoint_seconds, bool quiet, py::object progress) {
  vkr::recon::ReconstructOptions options;
  options.scene = scene;
  options.output_dir = output_dir;
  options.resume = resume;
  options.time_limit = time_limit;
  options.temperatures = temperatures;
  options.checkpoint_seconds = checkpoint_seconds;
  options.quiet = quiet;
  std::optional<py::error_already_set> interrupted;
  options.should_stop = [&] {
    py::gil_scoped_acquire acquire;
    if (!interrupted && PyErr_CheckSignals() != 0) interrupted.emplace();  // takes the KeyboardInterrupt
    return interrupted.has_value();
  };
  int64_t evaluations = 0;  // hypotheses scored so far, at any pyramid level
  if (!progress.is_none()) {
    options.observer.evaluated = [&](int, size_t hypotheses) { evaluations += int64_t(hypotheses); };
    options.observer.best = [&](const std::vector<double>& psi) {
      py::gil_scoped_acquire acquire;
      if (interrupted) return;
      try {
        progress(evaluations, py::cast(psi));
      } catch (py::error_already_set& e) {
        interrupted.emplace(std::move(e));  // should_stop sees it after this frame
      }
    };
  }
  vkr::recon::ReconstructSummary summary;
  {
    py::gil_scoped_release release;
    vkr::recon::Reconstruct(options, *SharedDevice(), &summary);
  }
  if (interrupted) throw std::move(*interrupted);
  return summary;
}

py::object JsonToPython(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

// The parameter table: one dict per parameter, in the scene's order.
py::list ParameterTable(const vkr::recon::ReconstructSummary& s) {
  py::list rows;
  for (const vkr::opt::ParameterSummary& p : s.sampler.parameters) {
    py::dict row;
    row["name"] = p.name;
    row["map"] = p.map;
    row["mean"] = p.mean;
    row["sd"] = p.sd;
    row["q025"] = p.q025;
    row["q975"] = p.q975;
    row["ess"] = p.ess;
    row["rhat"] = p.rhat;
    rows.append(row);
  }
  return rows;
}

// The posterior draws (PosteriorDraws): D × P values, and each draw's chain.
py::tuple Draws(const vkr::recon::ReconstructSummary& s) {
  const std::vector<const vkr::opt::Sample*> rows = vkr::recon::PosteriorDraws(s.sampler);
  const py::ssize_t p = py::ssize_t(s.sampler.parameters.size());
  py::array_t<double> draws(std::vector<py::ssize_t>{py::ssize_t(rows.size()), p});  // a shape, not (count, data)
  py::array_t<int> chain(py::ssize_t(rows.size()));
  for (size_t d = 0; d < rows.size(); ++d) {
    std::copy(rows[d]->psi.begin(), rows[d]->psi.end(), draws.mutable_data(py::ssize_t(d), 0));
    chain.mutable_at(py::ssize_t(d)) = rows[d]->chain;
  }
  return py::make_tuple(draws, chain);
}

void BindReconstruct(py::module_& m) {
  using vkr::recon::ReconstructSummary;
  py::class_<ReconstructSummary>(m, "ReconstructSummary",
                                 "What a reconstruction found: map.json's content, and the draws.")
      .def_property_readonly("termination", [](const ReconstructSummary& s) { return vkr::opt::ToString(s.termination); })
      .def_property_readonly("completed", &ReconstructSummary::completed)
      .def_property_readonly("parameters", &ParameterTable)
      .def_property_readonly("parameter_names", [](const ReconstructSummary& s) {
        std::vector<std::string> names;
        for (const auto& p : s.sampler.parameters) names.push_back(p.name);
        return names;
      })
      .def_property_readonly("map", [](const ReconstructSummary& s) { return py::array(py::cast(s.map())); })
      .def_property_readonly("log_posterior", [](const ReconstructSummary& s) { return s.sampler.map_log_posterior; })
      .def_property_readonly("draws", [](const ReconstructSummary& s) { return py::object(Draws(s)[0]); },
                             "D x P posterior draws (every chain from its burn-in on), in parameter_names' order")
      .def_property_readonly("draw_chains", [](const ReconstructSummary& s) { return py::object(Draws(s)[1]); },
                             "the chain of each row of draws")
      // A stopped run has no diagnosis: verdict None, not ok.
      .def_property_readonly("verdict", [](const ReconstructSummary& s) -> py::object {
        return s.completed() ? py::str(vkr::recon::ToString(s.diagnosis.verdict)) : py::object(py::none());
      })
      .def_property_readonly("ok", [](const ReconstructSummary& s) { return s.completed() && s.diagnosis.ok(); })
      .def_property_readonly("notes", [](const ReconstructSummary& s) { return s.diagnosis.notes; })
      .def_property_readonly("output_dir", [](const ReconstructSummary& s) { return s.output_dir; })
      .def_property_readonly("written", [](const ReconstructSummary& s) { return s.written; })
      .def("brief_report", &ReconstructSummary::BriefReport)
      .def("full_report", &ReconstructSummary::FullReport)
      .def("to_json", [](const ReconstructSummary& s) { return JsonToPython(s.ToJson()); },
           "map.json's content as a dict (non-finite numbers are None)");

  m.def("reconstruct", &Reconstruct, py::arg("scene"), py::arg("output_dir"), py::kw_only(),
        py::arg("resume") = false, py::arg("time_limit") = -1.0, py::arg("temperatures") = 0,
        py::arg("checkpoint_seconds") = 5.0, py::arg("quiet") = true, py::arg("progress") = py::none(),
        "Runs `vkrecon run` on the scene into output_dir (map.json and every other output) and returns "
        "its summary. The scene's sampler block (Scene.load(set=[\"sampler.iterations=200\"])) says how "
        "long; time_limit < 0: sampler.time_limit. Ctrl-C checkpoints, then raises KeyboardInterrupt. "
        "progress(evaluations, best): called after every sampler frame (and where a search finds a better "
        "point) with the hypotheses scored so far (at any pyramid level) and the running MAP (a list, in the scene's "
        "parameter order); an exception it raises checkpoints the run and is raised again.");
  m.def("render", &Render, py::arg("scene"), py::arg("at") = py::none(), py::arg("camera") = py::none(),
        py::arg("texture") = py::none(), py::arg("scale") = 1.0, py::arg("atlas") = 2048,
        "One scene camera's view at `at` (default: the initial values) as an H x W x 4 float32 array, as "
        "`vkrecon render --camera` writes it: textured by `texture` (a run's composite.exr) or by the "
        "albedo; alpha 0 off the surface.");
  m.def("load_image", [](const std::filesystem::path& file) { return ImageArray(vkr::LoadImage(file)); },
        py::arg("file"), "An image file (EXR, PNG, JPEG, PGM/PPM) as an H x W x 4 float32 array.");
}

}  // namespace

PYBIND11_MODULE(_vkrecon, m) {
  m.doc() = "vkrecon's library: scenes, the likelihood on a batch of hypotheses, the --at format, runs, views";
  static py::exception<vkr::InputError> input_error(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const vkr::InputError& e) {
      input_error(e.what());
    }
  });

  m.def("validation_messages", [] { return SharedDevice()->validation_messages(); },
        "What the Vulkan validation layer reported so far (VKRECON_VALIDATION=1 turns it on).");

  py::class_<vkr::Scene, std::shared_ptr<vkr::Scene>>(m, "Scene")
      .def_static("load", &LoadScene, py::arg("file"), py::arg("set") = std::vector<std::string>{},
                  py::arg("require_images") = true,
                  "Loads a scene file, with --set style overrides (\"likelihood.sigma=4\", …); "
                  "require_images=False for a scene whose photographs are still to be made.")
      .def_property_readonly("file", [](const vkr::Scene& s) { return s.file; })
      .def_property_readonly("parameter_names", &ParameterNames)
      .def_property_readonly("initial_values", [](const vkr::Scene& s) { return py::array(py::cast(s.InitialValues())); })
      .def("values_from_file", [](const vkr::Scene& s, const std::filesystem::path& f) {
            return py::array(py::cast(s.ValuesFromFile(f)));
          }, py::arg("file"), "Reads an --at file: every parameter, no unknown name.")
      .def("write_values", [](const vkr::Scene& s, const std::filesystem::path& f,
                              py::array_t<double, py::array::c_style | py::array::forcecast> v) {
            s.WriteValues(f, Row(s, v));
          }, py::arg("file"), py::arg("values"), "Writes values as an --at file.");

  py::class_<PyLikelihood>(m, "Likelihood")
      .def(py::init(&MakeLikelihood), py::arg("scene"), py::arg("batch") = 16, py::arg("level") = 0,
           py::arg("chi2_correction") = true,
           "The scene's likelihood (its `likelihood` settings) on this process's Vulkan device.")
      .def_property_readonly("kind", [](const PyLikelihood& l) { return l.likelihood->kind(); })
      .def_property_readonly("levels", [](const PyLikelihood& l) { return l.likelihood->levels(); })
      .def_property_readonly("max_batch", [](const PyLikelihood& l) { return l.likelihood->max_batch(); })
      .def_property_readonly("sigma", [](const PyLikelihood& l) { return l.likelihood->model().sigma; })
      .def_property("level", [](const PyLikelihood& l) { return l.likelihood->level(); },
                    [](PyLikelihood& l, int level) {
                      if (level < 0 || level >= l.likelihood->levels()) throw py::value_error("level out of range");
                      l.likelihood->SetLevel(level);
                    })
      .def("calibrate_photometric", [](PyLikelihood& l, py::array_t<double, py::array::c_style | py::array::forcecast> at) {
            const std::vector<double> psi = Row(*l.scene, at);
            nlohmann::json j;
            {
              py::gil_scoped_release release;
              j = l.likelihood->CalibratePhotometric(psi);
            }
            return py::module_::import("json").attr("loads")(j.dump());
          }, py::arg("at"),
          "Fits the per-camera colour correction at `at` and scores with it from now on, as "
          "`vkrecon likelihood --at` does before it evaluates; None when the scene has none.")
      .def("evaluate", &Evaluate, py::arg("batch"),
           "K x P parameter values -> dict of K-arrays: total (log likelihood + edge term + occlusion "
           "prior, what `vkrecon likelihood` prints as total), log_likelihood, log_occlusion_prior, "
           "log_edges (0 without likelihood.edges), sum_squares, dof, seen_multi, seen_once.");
  BindReconstruct(m);
}
