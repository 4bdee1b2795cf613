#pragma once
// The intervals a run states, at the κ the noise calls for (docs/internals/LIKELIHOOD.md,
// "Honest intervals").
//
// Two estimates of κ come out of every calibration. The block sandwich's measures the whole
// variability of the per-texel score, the deterministic misfit included, and on photographs
// the scene explains exactly it is many times what the noise gives: intervals far wider than
// the errors. The noise's (NoiseCorrelation.h) counts how many texels share one pixel's noise.
//
// Sampling at the noise's κ mixes badly: the likelihood's roughness at small scales
// (rasterisation, 8-bit views) is divided by a far smaller κ. So by default the chains sample
// at the sandwich's κ, and the summaries are stated at the noise's: near a mode the
// log-likelihood over κ is a Gaussian whose spread goes as √κ, so the draws' spread about the
// MAP shrinks by √(κ_noise/κ). That holds where the residuals look like noise. Where the
// diagnosis finds model error (something left out or misplaced), the misfit biases the MAP
// beyond any noise interval: the sandwich's wide intervals stay, and map.json says why.

#include <string>

#include <nlohmann/json.hpp>

#include "engine/scene/Scene.h"
#include "pipelines/model/LikelihoodSettings.h"
#include "optimiser/Sampler.h"
#include "recon/Diagnosis.h"

namespace vkr::recon {

struct NoiseIntervals {
  double kappa = 1.0;  // the κ the intervals are stated at
  double scale = 1.0;  // √(kappa / the chains' κ): what the draws' spread about the MAP was multiplied by
  std::string from;    // "noise", "sandwich" (with `why`), "fixed", or "chains" (sampled at κ_noise)
  std::string why;     // why the sandwich's were kept, when they were
};

// Which κ the intervals of a run with these settings, calibration (map.json's) and verdict
// are stated at.
NoiseIntervals ChooseNoiseIntervals(const LikelihoodSettings& settings, const nlohmann::json& calibration,
                                    Diagnosis::Verdict verdict);

// The factor a parameter's spread (the chains' sd `sd`) is multiplied by when the intervals are
// stated at a κ whose likelihood-only spread is `scale` times the chains'. Only the part the
// curvature at the mode explains shrinks: where the chains spread wider than the Laplace sd
// `laplace_sd`, the likelihood is flatter than a Gaussian there (a plateau, a ridge of nearly
// equal fits), and tempering leaves that excess variance sd² − laplace_sd² as it is. The
// Gaussian part shrinks by `scale` under a uniform prior (`prior_sd` infinite), less where a
// normal prior of sd `prior_sd` holds the parameter too, not at all where the prior alone does.
// A `laplace_sd` that is not a positive number counts the whole spread as Gaussian.
double SpreadFactor(double scale, double sd, double prior_sd, double laplace_sd);

// Mean and quantiles moved toward the MAP, sd multiplied, by each parameter's SpreadFactor
// (`prior_sd[i]`: a normal prior's sd, infinite or absent for a uniform one); the Laplace sd by
// its own. chain.csv keeps the draws as sampled.
void ScaleIntervals(double scale, const std::vector<double>& prior_sd, opt::SamplerSummary* summary);

nlohmann::json ToJson(const NoiseIntervals& intervals);

}  // namespace vkr::recon
