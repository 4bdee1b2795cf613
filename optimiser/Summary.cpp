// Posterior statistics, reports, map.json and chain.csv.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <locale>
#include <sstream>

#include <nlohmann/json.hpp>

#include "optimiser/SamplerState.h"
#include "optimiser/Statistics.h"

namespace vkr::opt {



const char* ToString(Termination termination) {
  switch (termination) {
    case Termination::Completed: return "completed";
    case Termination::Stopped: return "stopped";
    case Termination::Failed: return "failed";
  }
  return "?";
}

bool FromString(const std::string& text, Termination* termination) {
  for (Termination t : {Termination::Completed, Termination::Stopped, Termination::Failed})
    if (text == ToString(t)) {
      *termination = t;
      return true;
    }
  return false;
}

namespace detail {

std::vector<std::vector<std::vector<double>>> PosteriorDraws(const State& s) {
  const int d = s.dimension(), chains = s.PosteriorChains();
  const int burn_in = s.options.BurnIn();
  std::vector<std::vector<std::vector<double>>> draws(
      size_t(d), std::vector<std::vector<double>>{size_t(chains)});
  for (const Sample& row : s.samples) {
    if (row.iteration < burn_in || row.chain >= chains) continue;
    for (int i = 0; i < d; ++i) draws[size_t(i)][size_t(row.chain)].push_back(row.psi[size_t(i)]);
  }
  return draws;
}

void MeasureConvergence(State& s) {
  s.max_rhat = s.min_ess = kNaN;
  bool undefined = false;
  for (const auto& chains : PosteriorDraws(s)) {
    const double rhat = RankNormalizedSplitRhat(chains), ess = BulkEffectiveSampleSize(chains);
    // An undefined statistic (too few draws, a chain that never moved) is not convergence.
    if (std::isnan(rhat) || std::isnan(ess)) undefined = true;
    if (!std::isnan(rhat) && !(rhat <= s.max_rhat)) s.max_rhat = rhat;
    if (!std::isnan(ess) && !(ess >= s.min_ess)) s.min_ess = ess;
  }
  if (undefined) s.max_rhat = kInf;
}

SamplerSummary Summarise(const State& s) {
  SamplerSummary out;
  out.iterations = s.iteration;
  out.burn_in = s.options.BurnIn();
  out.ended_by = s.ended_by;
  out.max_rhat = s.max_rhat;
  out.min_ess = s.min_ess;
  out.refine_steps = s.refine.step;
  out.frames = s.frame;
  out.evaluations = s.evaluations;
  out.chain = s.samples;

  const bool have_map = s.best.valid && s.best.level == 0 && s.phase != Phase::Start;
  if (s.phase != Phase::Done) {
    out.termination = Termination::Stopped;
    out.message = "at iteration " + std::to_string(s.iteration) + " of " +
                  std::to_string(s.options.iterations) + " (" + ToString(s.phase) + ")";
  } else if (!have_map) {
    out.termination = Termination::Failed;
    out.message = "no hypothesis had a finite log posterior at level 0";
  } else {
    out.termination = Termination::Completed;
  }
  if (have_map) {
    out.map = s.best.psi;
    out.map_log_prior = s.best.log_prior;
    out.map_log_likelihood = s.best.log_likelihood;
    out.map_log_posterior = s.best.log_posterior();
  } else {
    out.map_log_prior = out.map_log_likelihood = out.map_log_posterior = kNaN;
  }
  out.sampling_map_log_posterior =
      s.phase == Phase::Refining || s.phase == Phase::Done ? s.sampling_best : out.map_log_posterior;
  out.calibration = s.calibration;

  const auto draws = PosteriorDraws(s);
  for (int i = 0; i < s.dimension(); ++i) {
    ParameterSummary p;
    p.name = s.parameters[size_t(i)].name;
    p.map = have_map ? s.best.psi[size_t(i)] : kNaN;
    std::vector<double> pooled;
    for (const auto& chain : draws[size_t(i)]) pooled.insert(pooled.end(), chain.begin(), chain.end());
    p.mean = Mean(pooled);
    p.sd = StandardDeviation(pooled);
    p.q025 = Quantile(pooled, 0.025);
    p.q975 = Quantile(pooled, 0.975);
    p.ess = BulkEffectiveSampleSize(draws[size_t(i)]);
    p.rhat = RankNormalizedSplitRhat(draws[size_t(i)]);
    p.laplace_sd = s.laplace.rows() == s.dimension() ? std::sqrt(s.laplace(i, i)) : kNaN;
    out.parameters.push_back(p);
  }

  const auto ratio = [](int64_t a, int64_t b) { return b ? double(a) / double(b) : kNaN; };
  for (const ChainState& c : s.chains) {
    ChainSummary cs;
    for (const Replica& r : c.replicas) cs.replica_acceptance.push_back(ratio(r.accepted, r.proposed));
    for (size_t k = 0; k < c.swap_attempts.size(); ++k)
      cs.swap_acceptance.push_back(ratio(c.swap_accepts[k], c.swap_attempts[k]));
    cs.acceptance = cs.replica_acceptance.front();
    int64_t proposed = 0, accepted = 0;
    for (const Replica& r : c.replicas) proposed += r.independent_proposed, accepted += r.independent_accepted;
    cs.independence_acceptance = ratio(accepted, proposed);
    out.chains.push_back(cs);
  }
  out.posterior_chains = s.PosteriorChains();
  out.evidence = EstimateFromLadder(s);
  return out;
}

}  // namespace detail

namespace {

std::string Fixed(double v, int precision = 4) {
  std::ostringstream o;
  o.imbue(std::locale::classic());
  o << std::setprecision(precision) << v;
  return o.str();
}

// Worst R̂ and smallest ESS over the parameters (NaN-aware).
void Diagnostics(const SamplerSummary& s, double* max_rhat, double* min_ess) {
  *max_rhat = detail::kNaN;
  *min_ess = detail::kNaN;
  for (const ParameterSummary& p : s.parameters) {
    if (std::isfinite(p.rhat) && !(p.rhat <= *max_rhat)) *max_rhat = p.rhat;
    if (std::isfinite(p.ess) && !(p.ess >= *min_ess)) *min_ess = p.ess;
  }
}

nlohmann::json Nullable(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

}  // namespace

std::string SamplerSummary::BriefReport() const {
  double max_rhat, min_ess;
  Diagnostics(*this, &max_rhat, &min_ess);
  double acceptance = 0.0;
  for (const ChainSummary& c : chains) acceptance += c.acceptance / double(chains.size());
  std::string line = std::string("sampler ") + ToString(termination) + ": " +
                     std::to_string(iterations) + " iterations × " + std::to_string(chains.size()) +
                     " chains, " + std::to_string(refine_steps) + " refinement steps, " +
                     std::to_string(frames) + " frames, " + std::to_string(evaluations) +
                     " evaluations; log posterior at MAP " + Fixed(map_log_posterior, 10) +
                     ", acceptance " + Fixed(acceptance, 3) + ", max R̂ " + Fixed(max_rhat, 4) +
                     ", min ESS " + Fixed(min_ess, 4);
  if (!message.empty()) line += " (" + message + ")";
  return line;
}

std::string SamplerSummary::FullReport() const {
  std::ostringstream o;
  o.imbue(std::locale::classic());
  o << BriefReport() << "\n\n";
  o << "log posterior at MAP " << Fixed(map_log_posterior, 12) << " (sampling alone "
    << Fixed(sampling_map_log_posterior, 12) << "), log likelihood " << Fixed(map_log_likelihood, 12)
    << ", log prior " << Fixed(map_log_prior, 12) << "\n";
  o << "posterior over iterations [" << burn_in << ", " << iterations << ") of every chain\n\n";
  o << std::left << std::setw(16) << "parameter" << std::right;
  for (const char* h : {"map", "mean", "sd", "q025", "q975", "ess", "rhat"}) o << std::setw(13) << h;
  o << "\n";
  for (const ParameterSummary& p : parameters) {
    o << std::left << std::setw(16) << p.name << std::right;
    for (double v : {p.map, p.mean, p.sd, p.q025, p.q975, p.ess, p.rhat}) o << std::setw(13) << Fixed(v, 6);
    o << "\n";
  }
  o << "\nchain  acceptance per temperature (coldest first)   swap acceptance per pair\n";
  for (size_t c = 0; c < chains.size(); ++c) {
    o << std::setw(5) << c << " ";
    for (double a : chains[c].replica_acceptance) o << " " << Fixed(a, 3);
    o << "   ";
    for (double a : chains[c].swap_acceptance) o << " " << Fixed(a, 3);
    o << "\n";
  }
  if (evidence) o << "\n" << opt::BriefReport(*evidence) << "\n";
  return o.str();
}

nlohmann::json MapJson(const SamplerSummary& s) {
  nlohmann::json parameters = nlohmann::json::object();
  for (const ParameterSummary& p : s.parameters)
    parameters[p.name] = {{"map", Nullable(p.map)}, {"mean", Nullable(p.mean)},
                          {"sd", Nullable(p.sd)},   {"q025", Nullable(p.q025)},
                          {"q975", Nullable(p.q975)}, {"ess", Nullable(p.ess)},
                          {"rhat", Nullable(p.rhat)}, {"laplace_sd", Nullable(p.laplace_sd)},
                          {"interval_shift", Nullable(p.interval_shift)}};
  nlohmann::json chains = nlohmann::json::array();
  for (const ChainSummary& c : s.chains) {
    nlohmann::json replica = nlohmann::json::array(), swap = nlohmann::json::array();
    for (double a : c.replica_acceptance) replica.push_back(Nullable(a));
    for (double a : c.swap_acceptance) swap.push_back(Nullable(a));
    chains.push_back({{"acceptance", Nullable(c.acceptance)},
                      {"replica_acceptance", replica},
                      {"swap_acceptance", swap},
                      {"independence_acceptance", Nullable(c.independence_acceptance)}});
  }
  nlohmann::json j = {{"parameters", parameters},
                      {"log_likelihood", Nullable(s.map_log_likelihood)},
                      {"log_prior", Nullable(s.map_log_prior)},
                      {"log_posterior", Nullable(s.map_log_posterior)},
                      {"chains", chains},
                      {"posterior_chains", s.posterior_chains},
                      {"calibration", s.calibration},
                      {"termination", ToString(s.termination)},
                      {"message", s.message},
                      {"iterations", s.iterations},
                      {"burn_in", s.burn_in},
                      {"sampling",
                       {{"ended_by", s.ended_by}, {"max_rhat", Nullable(s.max_rhat)}, {"min_ess", Nullable(s.min_ess)}}},
                      {"refine_steps", s.refine_steps},
                      {"frames", s.frames},
                      {"evaluations", s.evaluations}};
  if (s.evidence) j["evidence"] = ToJson(*s.evidence);
  return j;
}

void WriteChainCsv(std::ostream& out, const std::vector<Sample>& chain,
                   const std::vector<ParameterSpec>& parameters) {
  std::ostringstream o;
  o.imbue(std::locale::classic());
  o << std::setprecision(std::numeric_limits<double>::max_digits10);
  o << "iteration,chain,level,temperature,accepted,swapped,log_posterior,log_likelihood,log_prior";
  for (const ParameterSpec& p : parameters) o << "," << p.name;
  o << "\n";
  for (const Sample& row : chain) {
    o << row.iteration << "," << row.chain << "," << row.level << "," << row.temperature << ","
      << int(row.accepted) << "," << int(row.swapped) << "," << row.log_posterior() << ","
      << row.log_likelihood << "," << row.log_prior;
    for (double v : row.psi) o << "," << v;
    o << "\n";
  }
  out << o.str();
}

void WriteStanCsv(std::ostream& out, const SamplerSummary& summary, const std::vector<ParameterSpec>& parameters,
                  int chain, uint64_t seed) {
  std::ostringstream o;
  o.imbue(std::locale::classic());
  o << std::setprecision(std::numeric_limits<double>::max_digits10);
  int64_t draws = 0;
  for (const Sample& row : summary.chain) draws += row.chain == chain && row.iteration >= summary.burn_in;
  o << "# model = vkrecon\n"
    << "# method = sample (algorithm = Metropolis-Hastings with replica exchange, vkrecon)\n"
    << "# num_samples = " << draws << "\n"
    << "# num_warmup = 0\n"
    << "# save_warmup = 0\n"
    << "# thin = 1\n"
    << "# chain_id = " << chain + 1 << "\n"
    << "# seed = " << seed << "\n"
    << "# burn_in_iterations = " << summary.burn_in << "\n"
    << "lp__,accept_stat__";
  for (const ParameterSpec& p : parameters) o << "," << p.name;
  o << "\n";
  for (const Sample& row : summary.chain) {
    if (row.chain != chain || row.iteration < summary.burn_in) continue;
    o << row.log_posterior() << "," << (row.accepted ? 1 : 0);
    for (double v : row.psi) o << "," << v;
    o << "\n";
  }
  out << o.str();
}

}  // namespace vkr::opt
