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

// The factor a parameter's spread is multiplied by when the intervals are stated at a κ whose
// likelihood-only spread is `scale` times the chains': `scale` for a uniform prior
// (`prior_sd` infinite), nearer 1 where a normal prior of sd `prior_sd` holds the parameter
// too (posterior sd `sd`), 1 where the prior alone does.
double SpreadFactor(double scale, double sd, double prior_sd);

// Mean and quantiles moved toward the MAP, sd and the Laplace sd multiplied, by each
// parameter's factor: `scale` where the likelihood alone sets its spread (a uniform prior:
// `prior_sd` infinite or absent); less where a normal prior of sd `prior_sd[i]` holds it too,
// since only the likelihood's share of its precision grows (in the Gaussian approximation,
// parameter by parameter). chain.csv keeps the draws as sampled.
void ScaleIntervals(double scale, const std::vector<double>& prior_sd, opt::SamplerSummary* summary);

nlohmann::json ToJson(const NoiseIntervals& intervals);

}  // namespace vkr::recon
