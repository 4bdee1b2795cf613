#include "recon/SearchSetup.h"

#include "engine/common/InputError.h"
#include "engine/scene/SettingsReader.h"
#include "pipelines/model/LikelihoodSettings.h"
#include "pipelines/likelihood/LikelihoodTool.h"

namespace fs = std::filesystem;

namespace vkr::recon {

Scene LoadSearchScene(const fs::path& file, const std::vector<SceneOverride>& overrides) {
  Scene scene = LoadScene(file, overrides);
  ResolveAutoLikelihood(scene);  // atlas and levels "auto": map.json reports what was used
  if (scene.parameters.empty())
    throw InputError(scene.file.string(), "parameters", "nothing to reconstruct: the scene declares no parameter");
  return scene;
}

opt::SamplerOptions SamplerOptionsOf(const Scene& scene) {
  opt::SamplerOptions options;
  std::string why;
  const nlohmann::json block = SettingsReader(scene, "sampler").json();
  // `why` is "sampler.FIELD: problem" for what the JSON says, "FIELD must …" for what IsValid says.
  if (!opt::FromJson(block, &options, &why))
    throw InputError(scene.file.string(), why.rfind("sampler.", 0) == 0 ? "" : "sampler." + why.substr(0, why.find(' ')),
                     why);
  return options;
}

std::unique_ptr<Likelihood> MakeSearchLikelihood(vk::Device& device, const Scene& scene, int max_batch) {
  LikelihoodSetup setup;
  setup.max_batch = max_batch;
  std::unique_ptr<Likelihood> likelihood = MakeLikelihood(device, scene, setup);
  // The photographs' exposures differ: a first colour correction at the initial parameters,
  // on the coarsest level, where misregistration matters least (`run` refits it at the mode).
  // Done again, identically, when a run resumes before its first calibration.
  likelihood->SetLevel(likelihood->levels() - 1);
  likelihood->CalibratePhotometric(scene.InitialValues());
  likelihood->SetLevel(0);
  return likelihood;
}

void PreflightVisibility(const Scene& scene, Likelihood& likelihood) {
  const Evaluation e = likelihood.Evaluate({scene.InitialValues()})[0];
  if (e.scalars.seen_multi == 0)
    throw InputError(scene.file.string(), "cameras",
                     "at the initial parameters no surface point is seen by two cameras: the cameras "
                     "see nothing of the scene (check poses, priors and images)");
}

std::vector<opt::ParameterSpec> ParameterSpecs(const Scene& scene) {
  std::vector<opt::ParameterSpec> specs;
  for (const Parameter& p : scene.parameters) {
    opt::ParameterSpec s;
    s.name = p.name;
    s.prior = p.prior.kind == Prior::Kind::Uniform ? opt::PriorKind::Uniform : opt::PriorKind::Normal;
    s.a = p.prior.a;
    s.b = p.prior.b;
    s.bounds = p.bounds;
    s.init = p.init;
    specs.push_back(s);
  }
  return specs;
}

}  // namespace vkr::recon
