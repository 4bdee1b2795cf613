#include "pipelines/likelihood/LikelihoodTool.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <system_error>

#include "engine/common/InputError.h"
#include "engine/image/ChiSquareRamp.h"
#include "engine/image/LinePlot.h"
#include "engine/geometry/SceneGeometry.h"
#include "pipelines/likelihood/ImageLikelihood.h"
#include "pipelines/likelihood/Residuals.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"

namespace fs = std::filesystem;

namespace vkr {
namespace {

// Forwards the common interface to a concrete likelihood; adapters add kind() and dumps.
template <class Concrete, class Options>
class Adapter : public Likelihood {
 public:
  Adapter(vk::Device& device, const Scene& scene, const Options& options)
      : device_(&device), likelihood_(device, scene, options) {}

  const LikelihoodModel& model() const override { return likelihood_.options().model; }
  int max_batch() const override { return likelihood_.options().max_batch; }
  void SetLevel(int level) override { likelihood_.SetLevel(level); }
  int level() const override { return likelihood_.level(); }
  int levels() const override { return likelihood_.levels(); }
  void SetSigma(double sigma_255) override { likelihood_.SetSigma(sigma_255); }
  std::vector<Evaluation> Evaluate(const std::vector<std::vector<double>>& batch) override {
    return likelihood_.Evaluate(batch);
  }
  std::map<std::string, double> LastPassTimesMs() const override { return likelihood_.LastPassTimesMs(); }

 protected:
  vk::Device* device_;
  Concrete likelihood_;
};

// The surface-space likelihood behind the common interface.
class SurfaceAdapter final : public Adapter<SurfaceLikelihood, SurfaceLikelihoodOptions> {
 public:
  using Adapter::Adapter;
  std::string kind() const override { return "surface"; }
  void SetPositionSd(double pixels) override { likelihood_.SetPositionSd(pixels); }

  nlohmann::json CalibratePhotometric(const std::vector<double>& psi) override {
    const PhotometricModel model = likelihood_.options().photometric;
    if (model == PhotometricModel::None) return nullptr;
    const SurfaceDump dump = likelihood_.EvaluateAndDump(psi);
    const PhotometricCorrection correction = FitPhotometric(dump.view_textures, model);
    likelihood_.SetPhotometric(correction);
    return ToJson(correction);
  }
  void RestorePhotometric(const nlohmann::json& correction) override {
    if (correction.is_null()) return;
    likelihood_.SetPhotometric(PhotometricFromJson(correction, int(likelihood_.scene().cameras.size())));
  }
  ClutterMasks MaskClutter(const std::vector<double>& psi) override {
    ClutterMasks clutter = FindClutter(*device_, likelihood_, psi);
    likelihood_.SetClutterMasks(clutter.masks);
    return clutter;
  }
  void SetClutterMasks(const std::vector<Image>& masks) override { likelihood_.SetClutterMasks(masks); }
  void ClearClutterMasks() override { likelihood_.ClearClutterMasks(); }
  NoiseCorrelationEstimate NoiseCorrelation(const std::vector<double>& psi) override {
    const SurfaceDump dump = likelihood_.EvaluateAndDump(psi);
    return ResidualCorrelation(
        StandardisedResiduals(dump, likelihood_.options().model, likelihood_.photometric()),
        kNoiseCorrelationRadius);
  }

  LikelihoodDump EvaluateAndDump(const std::vector<double>& psi, Evaluation* evaluation) override {
    SurfaceDump surface = likelihood_.EvaluateAndDump(psi, evaluation);
    const std::vector<CameraModel>& cameras = likelihood_.scene().cameras;
    LikelihoodDump dump;
    for (size_t i = 0; i < surface.view_textures.size(); ++i) {
      const std::string camera = i < cameras.size() ? cameras[i].name : std::to_string(i);
      dump.images.push_back({"view_" + camera, DumpImage::Kind::Colour, false,
                             std::move(surface.view_textures[i])});
    }
    dump.images.push_back({"composite", DumpImage::Kind::Colour, true, std::move(surface.composite)});
    dump.images.push_back({"deviation", DumpImage::Kind::Deviation, true, std::move(surface.deviation)});
    dump.images.push_back({"noise", DumpImage::Kind::Data, false, std::move(surface.noise)});
    if (!surface.edges.Empty()) dump.images.push_back({"edges", DumpImage::Kind::Data, false, std::move(surface.edges)});
    return dump;
  }
};

// The image-space likelihood (§4) behind the common interface. A dump holds, per ordered
// pair (s, t), the synthetic image s_{s,t} (t's view textured from r_s, thesis Figs 4.5–4.8)
// and its consistency with r_t: `synthetic_<t>_from_<s>` and `consistency_<t>_from_<s>`.
class ImageAdapter final : public Adapter<ImageLikelihood, ImageLikelihoodOptions> {
 public:
  using Adapter::Adapter;
  std::string kind() const override { return "image"; }

  LikelihoodDump EvaluateAndDump(const std::vector<double>& psi, Evaluation* evaluation) override {
    ImageDump image = likelihood_.EvaluateAndDump(psi, evaluation);
    const std::vector<CameraModel>& cameras = likelihood_.scene().cameras;
    LikelihoodDump dump;
    for (ImagePairDump& d : image.pairs) {
      const std::string pair =
          cameras[size_t(d.pair.target)].name + "_from_" + cameras[size_t(d.pair.source)].name;
      dump.images.push_back({"synthetic_" + pair, DumpImage::Kind::Colour, true, std::move(d.synthetic)});
      dump.images.push_back({"consistency_" + pair, DumpImage::Kind::Deviation, true, std::move(d.consistency)});
    }
    return dump;
  }
};

// A scene, the hypothesis of --at and a likelihood built for them; the likelihood may keep a
// reference to the scene, so the scene is declared first and outlives it.
struct Session {
  Scene scene;
  std::vector<double> at;
  std::unique_ptr<Likelihood> likelihood;
  nlohmann::json photometric;  // the colour correction fitted at `at` (null: none)
};

// Checks what can be checked before the (costly) likelihood is built.
Session Open(const LikelihoodToolOptions& options) {
  Session s;
  s.scene = LoadScene(options.scene_file, options.overrides);
  ResolveAutoLikelihood(s.scene);
  s.at = s.scene.ValuesFromFile(options.at_file);
  const int levels = LikelihoodSettingsOf(s.scene).levels;
  if (options.level < 0 || options.level >= levels)
    throw InputError("", "--level", "level " + std::to_string(options.level) + " is outside [0, " +
                                        std::to_string(levels - 1) + "] (likelihood.levels is " +
                                        std::to_string(levels) + ")");
  return s;
}

void Build(Session& s, vk::Device& device, const LikelihoodToolOptions& options, int max_batch) {
  LikelihoodSetup setup;
  setup.max_batch = max_batch;
  setup.chi2_correction = options.chi2_correction;
  setup.profile = options.profile;
  s.likelihood = MakeLikelihood(device, s.scene, setup);
  if (options.level >= s.likelihood->levels())
    throw InputError("", "--level", "level " + std::to_string(options.level) + " is outside [0, " +
                                        std::to_string(s.likelihood->levels() - 1) + "]");
  s.likelihood->SetLevel(options.level);
  // Exposure and white balance differ between photographs: fit the colour correction once,
  // at the hypothesis asked about, and keep it for every evaluation (a sweep's too).
  s.photometric = s.likelihood->CalibratePhotometric(s.at);
}

std::string Number(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char text[32];
  // Shortest text that reads back to the same double; independent of the locale.
  const auto result = std::to_chars(text, text + sizeof text, x);
  return std::string(text, result.ptr);
}


PassProfile ProfileBatch(Likelihood& likelihood, const std::vector<double>& psi, int repeats) {
  PassProfile p;
  p.batch = likelihood.max_batch();
  p.repeats = repeats;
  const std::vector<std::vector<double>> batch(size_t(p.batch), psi);
  likelihood.Evaluate(batch);  // warm-up: the first submission compiles the pipelines
  const auto start = std::chrono::steady_clock::now();
  for (int r = 0; r < repeats; ++r) {
    likelihood.Evaluate(batch);
    for (const auto& [pass, ms] : likelihood.LastPassTimesMs()) p.gpu_ms[pass] += ms / repeats;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  p.hypotheses_per_s = seconds > 0 ? double(p.batch) * repeats / seconds : 0.0;
  return p;
}

// The evaluation and its settings beside a dump, so it can be repeated and compared.
void WriteEvaluationJson(const fs::path& file, const LikelihoodToolOptions& options, const Session& s,
                         const LikelihoodReport& r) {
  nlohmann::ordered_json j;
  j["scene"] = fs::absolute(options.scene_file).string();
  nlohmann::ordered_json set = nlohmann::ordered_json::object();
  for (const SceneOverride& o : options.overrides) set[o.path] = o.value;
  j["set"] = set;
  nlohmann::ordered_json at = nlohmann::ordered_json::object();
  for (size_t p = 0; p < s.at.size(); ++p) at[s.scene.parameters[p].name] = s.at[p];
  j["at"] = at;
  j["kind"] = r.kind;
  j["level"] = r.level;
  j["sigma"] = r.sigma;
  j["chi2_correction"] = r.chi2_correction;
  const Evaluation& e = r.evaluation;
  j["log_likelihood"] = e.log_likelihood;
  j["log_occlusion_prior"] = e.log_occlusion_prior;
  j["log_edges"] = e.log_edges;
  j["edge_length"] = e.edge_length;
  j["total"] = e.total();
  j["sum_squares"] = e.scalars.sum_squares;
  j["dof"] = e.scalars.dof;
  j["seen_multi"] = e.scalars.seen_multi;
  j["seen_once"] = e.scalars.seen_once;
  j["seen_none"] = e.scalars.seen_none;
  j["interior"] = e.scalars.interior;
  j["masked"] = e.scalars.masked;
  j["views"] = e.scalars.views;
  j["outlier_views"] = e.scalars.outlier_views;
  j["unverified"] = e.scalars.unverified;
  j["chi2_per_dof"] = std::isfinite(r.chi2_per_dof) ? nlohmann::ordered_json(r.chi2_per_dof) : nullptr;
  j["photometric"] = r.photometric;
  std::ofstream out(file, std::ios::binary);
  if (!out || !(out << j.dump(2) << "\n") || !out.flush())
    throw std::runtime_error("cannot write " + file.string());
}

// A camera name as a file-name component.
std::string FileStem(std::string name) {
  for (char& c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) c = '_';
  return name;
}

}  // namespace

std::unique_ptr<Likelihood> MakeLikelihood(vk::Device& device, const Scene& scene, const LikelihoodSetup& setup) {
  const LikelihoodKind kind = LikelihoodSettingsOf(scene).kind;
  if (kind == LikelihoodKind::Surface) {
    SurfaceLikelihoodOptions options = SurfaceLikelihoodOptions::FromScene(scene);
    options.model.chi2_correction = setup.chi2_correction;
    options.max_batch = setup.max_batch;
    options.profile = setup.profile;
    std::string why;
    if (!options.IsValid(&why)) throw InputError(scene.file.string(), "likelihood", why);
    return std::make_unique<SurfaceAdapter>(device, scene, options);
  }
  {
    ImageLikelihoodOptions options = ImageLikelihoodOptions::FromScene(scene);
    options.model.chi2_correction = setup.chi2_correction;
    options.max_batch = setup.max_batch;
    options.profile = setup.profile;
    std::string why;
    if (!options.IsValid(&why)) throw InputError(scene.file.string(), "likelihood", why);
    return std::make_unique<ImageAdapter>(device, scene, options);
  }
}

LikelihoodReport EvaluateAt(const LikelihoodToolOptions& options, vk::Device& device) {
  if (options.profile && options.profile_repeats < 1)
    throw InputError("", "--profile", "needs at least one timed repetition");
  Session s = Open(options);
  Build(s, device, options, options.profile ? std::max(1, options.batch) : 1);

  LikelihoodReport r;
  r.kind = s.likelihood->kind();
  r.level = s.likelihood->level();
  r.sigma = s.likelihood->model().sigma;
  r.chi2_correction = s.likelihood->model().chi2_correction;
  r.photometric = s.photometric;
  if (options.dump_dir) {
    const LikelihoodDump dump = s.likelihood->EvaluateAndDump(s.at, &r.evaluation);
    r.dump_files = WriteDump(dump, *options.dump_dir);
    if (s.likelihood->kind() == "surface") {
      const LikelihoodSettings settings = LikelihoodSettingsOf(s.scene);
      const SceneGeometry geometry = BuildSceneGeometry(s.scene, s.scene.InitialValues(), settings.atlas, settings.charts);
      const fs::path csv = *options.dump_dir / "nodes.csv";
      const Image *deviation = nullptr, *noise = nullptr;
      for (const DumpImage& d : dump.images) {
        if (d.name == "deviation") deviation = &d.image;
        if (d.name == "noise") noise = &d.image;
      }
      if (deviation && noise) WriteNodeResidualsCsv(csv, NodeResiduals(s.scene, geometry.atlas, *deviation, *noise));
      r.dump_files.push_back(csv);
    }
  } else {
    r.evaluation = s.likelihood->Evaluate({s.at}).at(0);
  }
  r.chi2_per_dof = Chi2PerDof(r.evaluation.scalars, r.sigma);
  if (options.dump_dir) {
    const fs::path file = *options.dump_dir / "evaluation.json";
    WriteEvaluationJson(file, options, s, r);
    r.dump_files.push_back(file);
  }
  if (options.profile) r.profile = ProfileBatch(*s.likelihood, s.at, options.profile_repeats);
  return r;
}

std::string FormatReport(const LikelihoodReport& r) {
  std::string out;
  auto row = [&](const std::string& name, const std::string& value) {
    out += name + std::string(name.size() < 22 ? 22 - name.size() : 1, ' ') + value + "\n";
  };
  const Evaluation& e = r.evaluation;
  row("log_likelihood", Number(e.log_likelihood));
  row("log_occlusion_prior", Number(e.log_occlusion_prior));
  if (e.edge_length > 0.0) {
    row("log_edges", Number(e.log_edges));
    row("edge_length", Number(e.edge_length));
  }
  row("total", Number(e.total()));
  row("sum_squares", Number(e.scalars.sum_squares));
  row("dof", Number(e.scalars.dof));
  row("seen_multi", std::to_string(e.scalars.seen_multi));
  row("seen_once", std::to_string(e.scalars.seen_once));
  row("seen_none", std::to_string(e.scalars.seen_none));
  row("interior", std::to_string(e.scalars.interior));
  row("level", std::to_string(r.level));
  row("chi2_per_dof", Number(r.chi2_per_dof));
  row("sigma", Number(r.sigma));
  row("chi2_correction", r.chi2_correction ? "on" : "off");
  row("kind", r.kind);
  if (r.profile) {
    const PassProfile& p = *r.profile;
    row("profile_batch", std::to_string(p.batch));
    row("profile_repeats", std::to_string(p.repeats));
    double total = 0.0;
    for (const auto& [pass, ms] : p.gpu_ms) {
      row("gpu_ms." + pass, Number(ms));
      total += ms;
    }
    row("gpu_ms.total", Number(total));
    row("hypotheses_per_s", Number(p.hypotheses_per_s));
  }
  return out;
}

std::vector<double> SweepSpec::Values() const {
  std::vector<double> values(size_t(std::max(steps, 0)));
  // LO + k(HI−LO)/(N−1), written so that round numbers stay round (−0.1, not −0.09999…).
  for (int k = 0; k < steps; ++k) values[size_t(k)] = (lo * (steps - 1 - k) + hi * k) / (steps - 1);
  if (steps >= 2) values.back() = hi;
  return values;
}

SweepSpec ParseSweep(const std::string& text) {
  auto fail = [&](const std::string& why) -> SweepSpec {
    throw InputError("", "--sweep", "'" + text + "': " + why + " (expected NAME=LO:HI:N)");
  };
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) return fail("no parameter name");
  SweepSpec spec;
  spec.parameter = text.substr(0, eq);
  std::vector<std::string> fields;
  for (size_t start = eq + 1;;) {
    const size_t colon = text.find(':', start);
    fields.push_back(text.substr(start, colon == std::string::npos ? std::string::npos : colon - start));
    if (colon == std::string::npos) break;
    start = colon + 1;
  }
  if (fields.size() != 3) return fail("expected three fields LO:HI:N, got " + std::to_string(fields.size()));
  auto number = [&](const std::string& field, const char* what) {
    double x = 0.0;
    const char* end = field.data() + field.size();
    const auto result = std::from_chars(field.data(), end, x);
    if (field.empty() || result.ec != std::errc() || result.ptr != end || !std::isfinite(x))
      fail(std::string(what) + " '" + field + "' is not a number");
    return x;
  };
  spec.lo = number(fields[0], "LO");
  spec.hi = number(fields[1], "HI");
  const double n = number(fields[2], "N");
  if (n != std::floor(n) || n < 2 || n > 1e6) return fail("N must be a whole number from 2 to 1000000");
  spec.steps = int(n);
  if (!(spec.lo < spec.hi)) return fail("LO must be below HI");
  return spec;
}

SweepResult Sweep(const LikelihoodToolOptions& options, const SweepSpec& spec, vk::Device& device,
                  const SweepProgress& progress) {
  Session s = Open(options);
  const int p = s.scene.ParameterIndex(spec.parameter);
  if (p < 0) {
    std::string names;
    for (const Parameter& q : s.scene.parameters) names += (names.empty() ? "" : ", ") + q.name;
    throw InputError("", "--sweep", "no parameter named '" + spec.parameter + "' in " + s.scene.file.string() +
                                        " (parameters: " + names + ")");
  }
  const Parameter& parameter = s.scene.parameters[size_t(p)];
  if (!parameter.Admissible(spec.lo) || !parameter.Admissible(spec.hi)) {
    const Prior& prior = parameter.prior;
    std::string support = prior.kind == Prior::Kind::Uniform
                              ? "prior uniform [" + Number(prior.a) + ", " + Number(prior.b) + "]"
                              : "prior normal";
    if (parameter.bounds)
      support += ", bounds [" + Number(parameter.bounds->first) + ", " + Number(parameter.bounds->second) + "]";
    throw InputError("", "--sweep", "the range [" + Number(spec.lo) + ", " + Number(spec.hi) + "] leaves the " +
                                        "support of '" + spec.parameter + "' (" + support + ")");
  }
  const int batch = std::clamp(options.batch, 1, spec.steps);
  Build(s, device, options, batch);

  SweepResult result;
  result.spec = spec;
  result.at_value = s.at[size_t(p)];
  result.batch = batch;
  const std::vector<double> values = spec.Values();
  for (size_t first = 0; first < values.size(); first += size_t(batch)) {
    const size_t count = std::min(size_t(batch), values.size() - first);
    std::vector<std::vector<double>> hypotheses(count, s.at);
    for (size_t k = 0; k < count; ++k) hypotheses[k][size_t(p)] = values[first + k];
    const std::vector<Evaluation> evaluations = s.likelihood->Evaluate(hypotheses);
    for (size_t k = 0; k < count; ++k) result.rows.push_back({values[first + k], evaluations.at(k)});
    if (progress) progress(int(first + count), int(values.size()));
  }
  return result;
}

void WriteSweepCsv(std::ostream& out, const SweepResult& sweep) {
  out << "value,loglik,log_likelihood,log_occlusion_prior,sum_squares,dof,seen_multi,seen_once,"
         "seen_none,interior,log_edges,edge_length\n";
  for (const SweepRow& r : sweep.rows) {
    const Evaluation& e = r.evaluation;
    out << Number(r.value) << ',' << Number(e.total()) << ',' << Number(e.log_likelihood) << ','
        << Number(e.log_occlusion_prior) << ',' << Number(e.scalars.sum_squares) << ','
        << Number(e.scalars.dof) << ',' << e.scalars.seen_multi << ',' << e.scalars.seen_once << ','
        << e.scalars.seen_none << ',' << e.scalars.interior << ',' << Number(e.log_edges) << ','
        << Number(e.edge_length) << '\n';
  }
}

Image PlotSweep(const SweepResult& sweep) {
  std::vector<double> x, y;
  for (const SweepRow& r : sweep.rows) {
    x.push_back(r.value);
    y.push_back(r.evaluation.total());
  }
  LinePlotOptions options;
  options.marker_x = sweep.at_value;
  return PlotLine(x, y, options).image;
}

Image DeviationRamp(const Image& deviation) {
  Image out(deviation.width, deviation.height, 0.0f);
  for (int y = 0; y < deviation.height; ++y)
    for (int x = 0; x < deviation.width; ++x) {
      const float* d = deviation.At(x, y);
      float* o = out.At(x, y);
      o[3] = 1.0f;
      if (d[3] <= 0.5f) continue;                   // off the surface: black
      if (d[2] > 0.5f) {                            // inside another primitive
        o[0] = o[1] = o[2] = 0.5f;
      } else if (d[1] <= 0.0f) {                    // seen by fewer than two views
        o[0] = o[1] = o[2] = 0.2f;
      } else {
        ChiSquareRamp(double(d[0]) / d[1], o);
      }
    }
  return out;
}

std::vector<fs::path> WriteDump(const LikelihoodDump& dump, const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string(), "", "cannot create the --dump folder: " + ec.message());
  std::vector<fs::path> written;
  for (const DumpImage& d : dump.images) {
    const fs::path exr = dir / (FileStem(d.name) + ".exr");
    if (d.kind != DumpImage::Kind::Colour) {
      // Data, not colour: encode so that WriteExr's decoding stores the numbers themselves.
      Image raw = d.image;
      for (size_t i = 0; i < raw.rgba.size(); i += 4)
        for (int c = 0; c < 3; ++c) raw.rgba[i + c] = LinearToSrgb(raw.rgba[i + c]);
      WriteExr(exr, raw);
    } else {
      WriteExr(exr, d.image);
    }
    written.push_back(exr);
    if (!d.preview) continue;
    Image preview = d.kind == DumpImage::Kind::Deviation ? DeviationRamp(d.image) : d.image;
    for (size_t i = 3; i < preview.rgba.size(); i += 4) preview.rgba[i] = 1.0f;  // opaque
    const fs::path png = dir / (FileStem(d.name) + ".png");
    WritePng(png, preview);
    written.push_back(png);
  }
  return written;
}

}  // namespace vkr
