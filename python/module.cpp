// `import vkrecon`: scenes, the likelihood on a numpy batch, and the `--at` format, through
// the same library calls the command line makes (docs/guide/PYTHON.md). The GIL is released
// while the GPU works; bad input raises vkrecon.InputError with the command line's one line.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "engine/common/InputError.h"
#include "engine/geometry/AtlasFootprint.h"
#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "pipelines/likelihood/LikelihoodTool.h"

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

}  // namespace

PYBIND11_MODULE(_vkrecon, m) {
  m.doc() = "vkrecon's library: scenes, the likelihood on a batch of hypotheses, the --at format";
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
           "K x P parameter values -> dict of K-arrays: total (log likelihood + occlusion prior, "
           "what `vkrecon likelihood` prints as total), log_likelihood, log_occlusion_prior, "
           "sum_squares, dof, seen_multi, seen_once.");
}
