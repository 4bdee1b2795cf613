#include "recon/RunOutputs.h"

#include <algorithm>
#include <limits>
#include <sstream>

#include "engine/image/Image.h"
#include "optimiser/JsonIntegers.h"
#include "pipelines/likelihood/NoiseCalibration.h"
#include "pipelines/likelihood/Residuals.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"
#include "pipelines/rendering/ModelExport.h"
#include "recon/AtomicWrite.h"
#include "recon/LikelihoodTarget.h"
#include "recon/NoiseIntervals.h"
#include "recon/RunStages.h"
#include "recon/SearchSetup.h"

namespace fs = std::filesystem;

namespace vkr::recon {
namespace {

// The σ (0–255) the run ended with: estimated at the mode with `sigma: auto`, else the given one.
double SigmaUsed(const LikelihoodSettings& settings, const opt::SamplerSummary& s) {
  if (s.calibration.is_object() && s.calibration.contains("sigma")) return s.calibration["sigma"].get<double>();
  return settings.sigma;
}

// The MAP climbs on at twice the atlas's side (FinerAtlasPolish.h), and is adopted when it
// ran. Not in the checkpoint either: deterministic, so a resumed finished run polishes
// alike. Its evaluations count as level −1 (four of level 0's) for the observer.
FinerAtlasPolish PolishFinerAndAdopt(const RunContext& run, const opt::Sampler& sampler,
                                     opt::SamplerSummary* summary) {
  const RunObserver& observer = run.options.observer;
  const FinerAtlasPolish finer = PolishAtFinerAtlas(
      run.device, run.scene, run.scene.overrides, *summary, sampler.options().finer_atlas_polish, run.quiet,
      [&](size_t n) {
        if (observer.evaluated) observer.evaluated(-1, n);
      });
  if (finer.ran) {
    AdoptPolishedMap(finer, run.scene, summary);
    summary->evaluations += finer.evaluations;
    if (observer.best) observer.best(summary->map);
  }
  return finer;
}

// The surface likelihood the outputs are rendered with: full resolution, one hypothesis, the
// run's calibrated σ, position sd and colour correction (its composite is the model's
// texture whichever likelihood sampled).
std::unique_ptr<SurfaceLikelihood> OutputLikelihood(const RunContext& run, const opt::SamplerSummary& summary,
                                                    SurfaceLikelihoodOptions* surface) {
  *surface = SurfaceLikelihoodOptions::FromScene(run.scene);
  surface->max_batch = 1;
  surface->model.sigma = SigmaUsed(run.likelihood, summary);
  if (summary.calibration.is_object()) {
    const NoiseCalibration calibration = NoiseCalibrationFromJson(summary.calibration);
    surface->model.position_sd = calibration.position_sd;
  }
  auto outputs = std::make_unique<SurfaceLikelihood>(run.device, run.scene, *surface);
  if (summary.calibration.is_object() && !summary.calibration["photometric"].is_null())
    outputs->SetPhotometric(PhotometricFromJson(summary.calibration["photometric"], int(run.scene.cameras.size())));
  return outputs;
}

// The final clutter masks: loaded from the checkpoint's files, written as the outputs'
// OUT/clutter/<camera>.png and set on `outputs`.
struct ClutterOutputs {
  std::vector<Image> masks;
  std::vector<double> share;
  nlohmann::json files = nlohmann::json::array();  // the outputs' names, clutter/<camera>.png
};

ClutterOutputs WriteClutter(const RunContext& run, const nlohmann::json& calibration, SurfaceLikelihood& outputs) {
  ClutterOutputs clutter;
  if (!calibration.is_object() || !calibration.contains("clutter")) return clutter;
  const fs::path& out = run.options.output_dir;
  fs::create_directories(out / "clutter");
  for (const auto& file : calibration["clutter"]["files"]) {
    clutter.masks.push_back(LoadImage(out / file.get<std::string>()));
    const std::string output = "clutter/" + run.scene.cameras[clutter.masks.size() - 1].name + ".png";
    WritePngAtomically(out / output, clutter.masks.back());
    clutter.files.push_back(output);
  }
  clutter.share = calibration["clutter"]["share"].get<std::vector<double>>();
  outputs.SetClutterMasks(clutter.masks);
  return clutter;
}

// The checkpoint's masks other than the final ones (the outputs', the checkpoint's) will
// never be read again.
void RemoveUnusedMasks(const RunContext& run, const nlohmann::json& calibration,
                       const nlohmann::json& chains_calibration) {
  auto lists = [](const nlohmann::json& calibration, const std::string& name) {
    return calibration.is_object() && calibration.contains("clutter") &&
           std::count(calibration["clutter"]["files"].begin(), calibration["clutter"]["files"].end(), name) > 0;
  };
  const fs::path masks = run.options.output_dir / kCheckpointMasks;
  if (!fs::is_directory(masks)) return;
  for (const auto& entry : fs::directory_iterator(masks)) {
    const std::string name = std::string(kCheckpointMasks) + "/" + entry.path().filename().string();
    if (!lists(calibration, name) && !lists(chains_calibration, name)) fs::remove(entry.path());
  }
}

// The outputs at the MAP that show the model: composite.exr/.png, model.glb and
// reprojections/, then the diagnosis of what they show. With the polish at the finer atlas,
// the MAP's log posterior is the one the run's calibrated likelihood gives it.
struct ModelOutputs {
  SceneGeometry geometry;
  Diagnosis diagnosis;
};

ModelOutputs WriteModel(const RunContext& run, const opt::Sampler& sampler, SurfaceLikelihood& outputs,
                        const SurfaceLikelihoodOptions& surface, const ClutterOutputs& clutter,
                        const FinerAtlasPolish& finer, opt::SamplerSummary* summary) {
  const fs::path& out = run.options.output_dir;
  Evaluation at_map;
  const SurfaceDump dump = outputs.EvaluateAndDump(summary->map, &at_map);
  if (finer.ran) {  // the adopted MAP as the run's (calibrated) likelihood scores it
    summary->map_log_prior = opt::LogPrior(sampler.parameters(), summary->map);
    summary->map_log_likelihood = at_map.total() / KappaFromJson(summary->calibration);
    summary->map_log_posterior = summary->map_log_prior + summary->map_log_likelihood;
  }
  const Image composite = DilateAtlas(dump.composite);
  WriteExr(out / "composite.exr", composite);
  WritePng(out / "composite.png", composite);
  SceneGeometry geometry = BuildSceneGeometry(run.scene, run.scene.InitialValues(), surface.atlas, surface.charts);
  WriteTexturedGlb(out / "model.glb", run.scene, geometry, summary->map, composite);
  ReprojectionNoise noise;
  noise.sigma_255 = surface.model.sigma;
  noise.position_sd = surface.model.position_sd;
  noise.photometric = outputs.photometric();
  noise.clutter = clutter.masks;
  const std::vector<Reprojection> reprojections =
      WriteReprojections(out / "reprojections", run.device, run.scene, geometry, summary->map, composite, noise);
  Diagnosis diagnosis =
      Diagnose(run.scene, at_map, surface.model.sigma, *summary,
               NodeResiduals(run.scene, geometry.atlas, dump.deviation, dump.noise), reprojections, clutter.share,
               &finer);
  return {std::move(geometry), std::move(diagnosis)};
}

// map.json's "settings": what the run used, so that it can be repeated.
nlohmann::json SettingsJson(const RunContext& run, const opt::Sampler& sampler) {
  const Scene& scene = run.scene;
  nlohmann::json settings = {
      {"scene", scene.file.string()},
      {"overrides", nlohmann::json::array()},
      {"device", run.device.name()},
      {"max_side", scene.max_side > 0 ? nlohmann::json(scene.max_side) : nlohmann::json(nullptr)},
      {"likelihood", ToJson(run.likelihood)},
      {"sampler", opt::ToJson(sampler.options())},
      {"time_limit", run.time_limit}};
  for (const SceneOverride& o : scene.overrides) settings["overrides"].push_back(o.path + "=" + o.value);
  return settings;
}

}  // namespace

void FinishAtMap(const RunContext& run, const opt::Sampler& sampler, const nlohmann::json& chains_calibration,
                 ReconstructSummary* summary, SceneGeometry* geometry) {
  summary->finer = PolishFinerAndAdopt(run, sampler, &summary->sampler);
  SurfaceLikelihoodOptions surface;
  const std::unique_ptr<SurfaceLikelihood> outputs = OutputLikelihood(run, summary->sampler, &surface);
  const ClutterOutputs clutter = WriteClutter(run, summary->sampler.calibration, *outputs);
  RemoveUnusedMasks(run, summary->sampler.calibration, chains_calibration);
  ModelOutputs model = WriteModel(run, sampler, *outputs, surface, clutter, summary->finer, &summary->sampler);
  for (const auto& file : clutter.files) summary->clutter_files.push_back(file.get<std::string>());
  summary->diagnosis = std::move(model.diagnosis);
  // After the diagnosis, which judges the chains' own spread; before anything states it.
  const NoiseIntervals intervals =
      ChooseNoiseIntervals(run.likelihood, summary->sampler.calibration, summary->diagnosis.verdict);
  std::vector<double> prior_sd;  // a normal prior's sd; a uniform one holds no spread near the mode
  for (const Parameter& parameter : run.scene.parameters)
    prior_sd.push_back(parameter.prior.kind == Prior::Kind::Uniform ? std::numeric_limits<double>::infinity()
                                                                    : parameter.prior.b);
  ScaleIntervals(intervals.scale, prior_sd, &summary->sampler);
  if (summary->sampler.calibration.is_object()) summary->sampler.calibration["intervals"] = ToJson(intervals);
  summary->settings = SettingsJson(run, sampler);
  const fs::path& out = run.options.output_dir;
  for (const char* name : {"composite.exr", "composite.png", "model.glb", "reprojections"})
    summary->written.push_back(out / name);
  for (const std::string& file : summary->clutter_files) summary->written.push_back(out / file);
  *geometry = std::move(model.geometry);
}

std::vector<fs::path> WriteRunFiles(const ReconstructSummary& summary, const Scene& scene) {
  const fs::path& out = summary.output_dir;
  const opt::SamplerSummary& sampler = summary.sampler;
  const std::vector<opt::ParameterSpec> parameters = ParameterSpecs(scene);
  scene.WriteValues(out / "at_map.json", sampler.map);
  {
    std::ostringstream csv;
    csv.imbue(std::locale::classic());
    opt::WriteChainCsv(csv, sampler.chain, parameters);
    WriteAtomically(out / "chain.csv", csv.str());
  }
  std::vector<fs::path> written = {out / "at_map.json", out / "chain.csv", out / "chains"};
  fs::create_directories(out / "chains");
  // The seed the sampler ran with, which a resumed run took from its checkpoint.
  const auto seed = opt::ReadInteger<uint64_t>(summary.settings.at("sampler").at("seed"));
  for (int c = 0; c < sampler.posterior_chains; ++c) {
    std::ostringstream stan;
    opt::WriteStanCsv(stan, sampler, parameters, c, seed);
    WriteAtomically(out / "chains" / ("stan-" + std::to_string(c + 1) + ".csv"), stan.str());
  }
  // Last, so that a map.json is the mark of a finished run: a run killed while writing its
  // outputs shows none, and its checkpoint writes them all again on resume.
  WriteAtomically(out / "map.json", summary.ToJson().dump(2) + "\n");
  written.push_back(out / "map.json");
  return written;
}

}  // namespace vkr::recon
