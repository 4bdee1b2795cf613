#pragma once
// The set-up every command that searches a scene's parameters shares: `run` samples them
// (Reconstruct.h), `fit` searches their mode with NLopt (Fit.h), the peers benchmark does
// both (bench/peers/PeersBench.h). The likelihood they search is LikelihoodTarget.h.

#include <filesystem>
#include <memory>
#include <vector>

#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "optimiser/Parameter.h"
#include "optimiser/SamplerOptions.h"
#include "pipelines/likelihood/Likelihood.h"

namespace vkr::recon {

// The scene file with its overrides and "auto" likelihood settings resolved (map.json reports
// what was used). InputError for bad input, and for a scene without parameters.
Scene LoadSearchScene(const std::filesystem::path& file, const std::vector<SceneOverride>& overrides);

// The scene's "sampler" block over SamplerOptions' defaults (the run's). InputError naming the
// scene file and the field.
opt::SamplerOptions SamplerOptionsOf(const Scene& scene);

// The scene's likelihood, scoring batches of up to `max_batch`, with its first colour
// correction made (see the .cpp) and left at level 0.
std::unique_ptr<Likelihood> MakeSearchLikelihood(vk::Device& device, const Scene& scene, int max_batch);

// Before spending minutes: can the cameras see the scene at all? InputError if not.
void PreflightVisibility(const Scene& scene, Likelihood& likelihood);

// The optimiser's description of the scene's parameters, in the scene's order.
std::vector<opt::ParameterSpec> ParameterSpecs(const Scene& scene);

}  // namespace vkr::recon
