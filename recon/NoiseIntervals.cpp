#include "recon/NoiseIntervals.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vkr::recon {

NoiseIntervals ChooseNoiseIntervals(const LikelihoodSettings& settings, const nlohmann::json& calibration,
                                    Diagnosis::Verdict verdict) {
  NoiseIntervals out;
  if (!calibration.is_object()) {
    out.from = "sandwich";
    out.why = "no calibration";
    return out;
  }
  const double chains = calibration.value("kappa", 1.0);
  out.kappa = chains;
  if (settings.kappa > 0.0) {
    out.from = "fixed";
    return out;
  }
  if (settings.kappa_estimate == KappaEstimate::Noise) {
    out.from = "chains";
    return out;
  }
  out.from = "sandwich";
  const nlohmann::json noise = calibration.value("noise_correlation", nlohmann::json());
  if (settings.kappa_estimate == KappaEstimate::Sandwich) {
    out.why = "likelihood.kappa is \"sandwich\"";
  } else if (!noise.is_object() || !noise.contains("kappa") || !noise["kappa"].is_number()) {
    out.why = "the noise's correlation was not measured";
  } else if (verdict == Diagnosis::Verdict::ModelError || verdict == Diagnosis::Verdict::Failed) {
    out.why = "the diagnosis finds model error: the misfit, not the noise, sets the error";
  } else if (verdict == Diagnosis::Verdict::NotDiagnosed) {
    out.why = "the run was not diagnosed";
  } else if (!(noise["kappa"].get<double>() < chains) || !(chains > 0.0)) {
    out.why = "the noise's kappa is not smaller";
  } else {
    out.from = "noise";
    out.kappa = noise["kappa"].get<double>();
    out.scale = std::sqrt(out.kappa / chains);
  }
  return out;
}

namespace {

// A Gaussian posterior's factor: its precision is the prior's plus the likelihood's, and only
// the likelihood's grows, by 1/scale².
double GaussianFactor(double scale, double sd, double prior_sd) {
  if (!(scale > 0.0)) return 1.0;
  if (!std::isfinite(prior_sd) || !(prior_sd > 0.0) || !(sd > 0.0)) return scale;
  const double prior_precision = 1.0 / (prior_sd * prior_sd);
  const double likelihood_precision = std::max(0.0, 1.0 / (sd * sd) - prior_precision);
  return std::sqrt((1.0 / (sd * sd)) / (prior_precision + likelihood_precision / (scale * scale)));
}

}  // namespace

double SpreadFactor(double scale, double sd, double prior_sd, double laplace_sd) {
  if (!(laplace_sd > 0.0) || !std::isfinite(laplace_sd) || !(sd > laplace_sd)) return GaussianFactor(scale, sd, prior_sd);
  const double gaussian = laplace_sd * GaussianFactor(scale, laplace_sd, prior_sd);
  return std::sqrt(sd * sd - laplace_sd * laplace_sd + gaussian * gaussian) / sd;
}

void ScaleIntervals(double scale, const std::vector<double>& prior_sd, opt::SamplerSummary* summary) {
  if (!(scale > 0.0) || scale == 1.0) return;
  for (size_t i = 0; i < summary->parameters.size(); ++i) {
    opt::ParameterSummary& p = summary->parameters[i];
    const double prior = i < prior_sd.size() ? prior_sd[i] : std::numeric_limits<double>::infinity();
    const double factor = SpreadFactor(scale, p.sd, prior, p.laplace_sd);
    // Toward the MAP, which lies inside the support: the moved values stay inside it too.
    for (double* v : {&p.mean, &p.q025, &p.q975}) *v = p.map + factor * (*v - p.map);
    p.laplace_sd *= SpreadFactor(scale, p.laplace_sd, prior, p.laplace_sd);
    p.sd *= factor;
  }
}

nlohmann::json ToJson(const NoiseIntervals& intervals) {
  nlohmann::json json = {{"kappa", intervals.kappa}, {"scale", intervals.scale}, {"from", intervals.from}};
  if (!intervals.why.empty()) json["why"] = intervals.why;
  return json;
}

}  // namespace vkr::recon
