#include "recon/ReconstructSummary.h"

#include <cmath>
#include <sstream>

#include "optimiser/JsonIntegers.h"

namespace vkr::recon {

nlohmann::json ToJson(const opt::MapSearchSummary& s) {
  return {{"method", "bobyqa"},
          {"evaluations", s.evaluations},
          {"cost", s.cost},
          {"map", s.map},
          {"log_posterior", s.map.empty() ? nlohmann::json() : nlohmann::json(s.log_posterior)},
          {"message", s.message}};
}

opt::MapSearchSummary StartSearchFromJson(const nlohmann::json& j) {
  opt::MapSearchSummary s;
  s.ok = true;
  s.evaluations = opt::ReadInteger<int64_t>(j.at("evaluations"));
  s.cost = j.at("cost").get<double>();
  s.map = j.at("map").get<std::vector<double>>();
  if (!j.at("log_posterior").is_null()) s.log_posterior = j.at("log_posterior").get<double>();
  s.message = j.at("message").get<std::string>();
  return s;
}

std::vector<const opt::Sample*> PosteriorDraws(const opt::SamplerSummary& summary) {
  std::vector<const opt::Sample*> draws;
  for (int c = 0; c < summary.posterior_chains; ++c)
    for (const opt::Sample& row : summary.chain)
      if (row.chain == c && row.iteration >= summary.burn_in) draws.push_back(&row);
  return draws;
}

nlohmann::json ReconstructSummary::ToJson() const {
  nlohmann::json map = opt::MapJson(sampler);
  map["start_search"] = recon::ToJson(start_search);
  auto finite = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
  // Both as they were compared: each with the nuisances fitted at it (ScoreModes).
  map["start_search"]["log_posterior_at_end"] = finite(start_compared.candidate);
  map["start_search"]["chains_log_posterior_at_end"] = finite(start_compared.chains);
  map["start_search"]["adopted"] = start_compared.adopted;
  map["polish"] = {{"method", "bobyqa"}, {"evaluations", polish.evaluations}, {"improved", polish.improved},
                   {"improvement", polish.improvement}, {"message", polish.message}};
  map["finer_atlas_polish"] = recon::ToJson(finer, sampler);
  if (!clutter_files.empty()) map["calibration"]["clutter"]["files"] = clutter_files;
  map["settings"] = settings;
  if (map.contains("evidence") && !evidence_likelihood.is_null()) map["evidence"]["likelihood"] = evidence_likelihood;
  map["diagnosis"] = diagnosis.json;
  return map;
}

std::string ReconstructSummary::BriefReport() const {
  std::ostringstream o;
  o.imbue(std::locale::classic());
  o << "vkrecon run " << opt::ToString(termination);
  if (!completed()) {
    o << ": stopped after " << sampler.iterations << " iterations; resume to finish";
    return o.str();
  }
  o.precision(10);
  o << ": " << sampler.iterations << " iterations x " << sampler.posterior_chains << " chains, " << sampler.evaluations
    << " evaluations; log posterior at MAP " << sampler.map_log_posterior << "; diagnosis "
    << ToString(diagnosis.verdict);
  return o.str();
}

std::string ReconstructSummary::FullReport() const {
  std::ostringstream o;
  o.imbue(std::locale::classic());
  o << BriefReport() << "\n\n" << sampler.FullReport() << "\n";
  o << "start search: " << start_search.evaluations << " evaluations"
    << (start_compared.adopted ? ", its mode adopted as the MAP" : "") << "\n";
  o << "polish: " << polish.evaluations << " evaluations, +" << polish.improvement << " nats\n";
  o << "finer atlas: "
    << (finer.ran ? std::to_string(finer.atlas) + "², max shift " + std::to_string(finer.MaxShiftSd()) + " sd"
                  : finer.skipped.empty() ? "off" : finer.skipped)
    << "\n";
  o << "diagnosis: " << ToString(diagnosis.verdict) << "\n";
  for (const std::string& note : diagnosis.notes) o << "  - " << note << "\n";
  if (!written.empty()) o << "wrote " << output_dir.string() << "/ (" << written.size() << " outputs)\n";
  return o.str();
}

}  // namespace vkr::recon
