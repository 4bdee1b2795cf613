// The sampler's state as JSON and back (Sampler::Checkpoint). Doubles are written with
// nlohmann's shortest round-trip formatting and read back by strtod, so every number comes
// back bit for bit; non-finite ones are written as strings. RNG streams are written with
// the engine's operator<< (the standard fixes its text form).

#include <cmath>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "optimiser/SamplerState.h"

namespace vkr::opt::detail {
namespace {

using nlohmann::json;

constexpr const char* kFormat = "vkrecon-sampler-checkpoint";
constexpr int kVersion = 2;  // 2: settling

json Numbers(const std::vector<double>& values) {
  json j = json::array();
  for (double v : values) j.push_back(JsonNumber(v));
  return j;
}

std::vector<double> ReadNumbers(const json& j) {
  std::vector<double> out;
  for (const json& v : j) out.push_back(ReadNumber(v));
  return out;
}

json Vector(const Eigen::VectorXd& v) { return Numbers(std::vector<double>(v.data(), v.data() + v.size())); }

Eigen::VectorXd ReadVector(const json& j, int size) {
  const std::vector<double> v = ReadNumbers(j);
  if (int(v.size()) != size) throw std::invalid_argument("vector of the wrong size");
  return Eigen::Map<const Eigen::VectorXd>(v.data(), size);
}

// Row-major.
json Matrix(const Eigen::MatrixXd& m) {
  std::vector<double> v;
  for (int i = 0; i < m.rows(); ++i)
    for (int k = 0; k < m.cols(); ++k) v.push_back(m(i, k));
  return Numbers(v);
}

Eigen::MatrixXd ReadMatrix(const json& j, int n) {
  const std::vector<double> v = ReadNumbers(j);
  if (int(v.size()) != n * n) throw std::invalid_argument("matrix of the wrong size");
  Eigen::MatrixXd m(n, n);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k) m(i, k) = v[size_t(i * n + k)];
  return m;
}

std::vector<double> ReadPsi(const json& j, int d) {
  std::vector<double> v = ReadNumbers(j);
  if (int(v.size()) != d) throw std::invalid_argument("hypothesis of the wrong size");
  return v;
}

json ReplicaToJson(const Replica& r) {
  return {{"psi", Numbers(r.psi)},
          {"log_prior", JsonNumber(r.log_prior)},
          {"log_likelihood", JsonNumber(r.log_likelihood)},
          {"proposed", r.proposed},
          {"accepted", r.accepted},
          {"independent_proposed", r.independent_proposed},
          {"independent_accepted", r.independent_accepted},
          {"log_scale", JsonNumber(r.log_scale)},
          {"adapt_count", r.adapt_count},
          {"adapt_mean", Vector(r.adapt_mean)},
          {"adapt_scatter", Matrix(r.adapt_scatter)}};
}

Replica ReplicaFromJson(const json& jr, int d) {
  Replica r;
  r.psi = ReadPsi(jr.at("psi"), d);
  r.log_prior = ReadNumber(jr.at("log_prior"));
  r.log_likelihood = ReadNumber(jr.at("log_likelihood"));
  r.proposed = ReadInteger<int64_t>(jr.at("proposed"));
  r.accepted = ReadInteger<int64_t>(jr.at("accepted"));
  // Absent from checkpoints written before independence proposals: none were made.
  if (jr.contains("independent_proposed")) {
    r.independent_proposed = ReadInteger<int64_t>(jr.at("independent_proposed"));
    r.independent_accepted = ReadInteger<int64_t>(jr.at("independent_accepted"));
  }
  r.log_scale = ReadNumber(jr.at("log_scale"));
  r.adapt_count = ReadInteger<int64_t>(jr.at("adapt_count"));
  r.adapt_mean = ReadVector(jr.at("adapt_mean"), d);
  r.adapt_scatter = ReadMatrix(jr.at("adapt_scatter"), d);
  return r;
}

// Written only for runs with the ladder (SamplerOptions::evidence_rungs), so that other
// checkpoints stay as they were; β comes back from the options.
json EvidenceToJson(const EvidenceState& e) {
  json j = {{"started", e.started}};
  if (!e.started) return j;
  j["start"] = e.start;
  j["collect_from"] = e.collect_from;
  j["rng"] = e.rng.State();
  j["rungs"] = json::array();
  for (const Replica& r : e.rungs) j["rungs"].push_back(ReplicaToJson(r));
  j["guess"] = json::array();
  for (const Eigen::MatrixXd& m : e.guess) j["guess"].push_back(Matrix(m));
  j["guess_centre"] = json::array();
  for (const Eigen::VectorXd& c : e.guess_centre) j["guess_centre"].push_back(Vector(c));
  j["swap_attempts"] = e.swap_attempts;
  j["swap_accepts"] = e.swap_accepts;
  j["draws"] = json::array();
  for (const std::vector<double>& rung : e.draws) j["draws"].push_back(Numbers(rung));
  return j;
}

EvidenceState EvidenceFromJson(const json& j, const State& s) {
  EvidenceState e;
  e.started = j.at("started").get<bool>();
  // A ladder from before its centres were kept starts afresh; the chains resume as they were.
  if (!e.started || !j.contains("guess_centre")) return EvidenceState();
  const int d = s.dimension();
  e.start = ReadInteger<int>(j.at("start"));
  e.collect_from = ReadInteger<int>(j.at("collect_from"));
  if (!e.rng.SetState(j.at("rng").get<std::string>())) throw std::invalid_argument("evidence: unreadable RNG state");
  e.beta = EvidenceLadder(s.options.evidence_rungs, s.options.evidence_alpha);
  const size_t rungs = e.beta.size();
  for (const json& jr : j.at("rungs")) e.rungs.push_back(ReplicaFromJson(jr, d));
  for (const json& m : j.at("guess")) e.guess.push_back(ReadMatrix(m, d));
  for (const json& c : j.at("guess_centre")) e.guess_centre.push_back(ReadVector(c, d));
  e.swap_attempts = ReadIntegers<int64_t>(j.at("swap_attempts"));
  e.swap_accepts = ReadIntegers<int64_t>(j.at("swap_accepts"));
  for (const json& rung : j.at("draws")) e.draws.push_back(ReadNumbers(rung));
  if (e.rungs.size() != rungs || e.guess.size() != rungs || e.guess_centre.size() != rungs || e.draws.size() != rungs ||
      e.swap_attempts.size() != rungs - 1 || e.swap_accepts.size() != rungs - 1)
    throw std::invalid_argument("evidence: not one entry per rung of the options' ladder");
  e.every = s.options.evidence_every;
  if (e.start < 0 || e.start > s.iteration || e.collect_from < e.start || (e.collect_from - e.start) % e.every != 0)
    throw std::invalid_argument("evidence: start or collect_from out of range");
  const size_t collected = e.Recorded(s.iteration);
  for (const std::vector<double>& rung : e.draws)
    if (rung.size() != collected) throw std::invalid_argument("evidence: not one draw per rung per step");
  return e;
}

}  // namespace

json JsonNumber(double value) {
  if (std::isfinite(value)) return value;
  if (std::isnan(value)) return "nan";
  return value > 0 ? "inf" : "-inf";
}

double ReadNumber(const json& j) {
  if (j.is_number()) return j.get<double>();
  if (j.is_string()) {
    const std::string s = j.get<std::string>();
    if (s == "nan") return kNaN;
    if (s == "inf") return kInf;
    if (s == "-inf") return -kInf;
  }
  throw std::invalid_argument("expected a number, found " + j.dump());
}

// Whether the samples' iteration column has iterations 0 … s.iteration − 1 in order, each
// with one row per chain (before cooling) or per posterior chain (after it).
bool RowsPerIteration(const json& iterations, const State& s) {
  const size_t chains = size_t(s.options.chains), all = size_t(s.PosteriorChains());
  size_t i = 0;
  for (int t = 0; t < s.iteration; ++t) {
    size_t n = 0;
    while (i < iterations.size() && ReadInteger<int>(iterations[i]) == t) ++n, ++i;
    if (n != chains && n != all) return false;
  }
  return i == iterations.size();
}

json StateToJson(const State& s) {
  json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["options"] = ToJson(s.options);
  j["parameters"] = json::array();
  for (const ParameterSpec& p : s.parameters) j["parameters"].push_back(ToJson(p));
  j["target_levels"] = s.target_levels;
  j["phase"] = ToString(s.phase);
  j["frame"] = s.frame;
  j["evaluations"] = s.evaluations;
  j["iteration"] = s.iteration;
  j["level"] = s.level;

  j["chains"] = json::array();
  for (const ChainState& c : s.chains) {
    json chain = {{"rng", c.rng.State()}, {"swap_attempts", c.swap_attempts},
                  {"swap_accepts", c.swap_accepts}, {"replicas", json::array()}};
    for (const Replica& r : c.replicas) chain["replicas"].push_back(ReplicaToJson(r));
    j["chains"].push_back(std::move(chain));
  }

  j["best"] = {{"valid", s.best.valid}, {"level", s.best.level}, {"psi", Numbers(s.best.psi)},
               {"log_prior", JsonNumber(s.best.log_prior)},
               {"log_likelihood", JsonNumber(s.best.log_likelihood)}};
  j["sampling_best"] = JsonNumber(s.sampling_best);
  j["convergence"] = {{"ended_by", s.ended_by}, {"max_rhat", JsonNumber(s.max_rhat)}, {"min_ess", JsonNumber(s.min_ess)}};

  const RefineState& r = s.refine;
  j["refine"] = {{"step", r.step},
                 {"have_point", r.have_point},
                 {"psi", Numbers(r.psi)},
                 {"log_prior", JsonNumber(r.log_prior)},
                 {"log_likelihood", JsonNumber(r.log_likelihood)},
                 {"gradient", Numbers(r.gradient)},
                 {"inverse_hessian", r.inverse_hessian.size() ? Matrix(r.inverse_hessian) : json::array()},
                 {"candidate", Numbers(r.candidate)},
                 {"step_scale", JsonNumber(r.step_scale)}};

  j["settle"] = {{"rounds", s.settle_rounds},
                {"calibration", s.calibration},
                {"laplace", s.laplace.size() ? Matrix(s.laplace) : json::array()},
                {"mode", Numbers(s.mode)}};

  // The chain so far, column by column.
  json iteration = json::array(), chain = json::array(), level = json::array(),
       temperature = json::array(), accepted = json::array(), swapped = json::array(),
       log_prior = json::array(), log_likelihood = json::array(), psi = json::array();
  for (const Sample& row : s.samples) {
    iteration.push_back(row.iteration);
    chain.push_back(row.chain);
    level.push_back(row.level);
    temperature.push_back(JsonNumber(row.temperature));
    accepted.push_back(row.accepted);
    swapped.push_back(row.swapped);
    log_prior.push_back(JsonNumber(row.log_prior));
    log_likelihood.push_back(JsonNumber(row.log_likelihood));
    psi.push_back(Numbers(row.psi));
  }
  j["samples"] = {{"iteration", iteration}, {"chain", chain}, {"level", level},
                  {"temperature", temperature}, {"accepted", accepted}, {"swapped", swapped},
                  {"log_prior", log_prior}, {"log_likelihood", log_likelihood}, {"psi", psi}};
  if (s.options.evidence_rungs > 0) j["evidence"] = EvidenceToJson(s.evidence);
  return j;
}

State StateFromJson(const json& j) {
  try {
    if (!j.is_object() || j.value("format", "") != kFormat)
      throw std::invalid_argument("not a sampler checkpoint");
    if (ReadInteger<int>(j.at("version")) != kVersion)
      throw std::invalid_argument("unsupported version " + j.at("version").dump());
    State s;
    std::string why;
    // A checkpoint from before cooling, independence proposals or fewer posterior chains
    // goes on as it began.
    s.options.cool_after_settling = false;
    s.options.independence_share = 0.0;
    s.options.posterior_chains = 0;
    if (!FromJson(j.at("options"), &s.options, &why)) throw std::invalid_argument(why);
    for (const json& p : j.at("parameters")) {
      ParameterSpec spec;
      if (!FromJson(p, &spec, &why)) throw std::invalid_argument(why);
      s.parameters.push_back(spec);
    }
    if (!IsValid(s.parameters, &why)) throw std::invalid_argument(why);
    const int d = s.dimension();
    s.target_levels = ReadInteger<int>(j.at("target_levels"));
    if (!FromString(j.at("phase").get<std::string>(), &s.phase))
      throw std::invalid_argument("unknown phase");
    s.frame = ReadInteger<int64_t>(j.at("frame"));
    s.evaluations = ReadInteger<int64_t>(j.at("evaluations"));
    s.iteration = ReadInteger<int>(j.at("iteration"));
    s.level = ReadInteger<int>(j.at("level"));
    if (s.iteration < 0 || s.iteration > s.options.iterations || s.level < 0 ||
        s.level >= s.target_levels)
      throw std::invalid_argument("iteration or level out of range");

    const json& chains = j.at("chains");
    if (int(chains.size()) != s.options.chains) throw std::invalid_argument("wrong number of chains");
    for (const json& jc : chains) {
      ChainState c;
      if (!c.rng.SetState(jc.at("rng").get<std::string>()))
        throw std::invalid_argument("unreadable RNG state");
      c.swap_attempts = ReadIntegers<int64_t>(jc.at("swap_attempts"));
      c.swap_accepts = ReadIntegers<int64_t>(jc.at("swap_accepts"));
      const json& replicas = jc.at("replicas");
      if (int(replicas.size()) != s.options.temperatures ||
          int(c.swap_attempts.size()) != s.options.temperatures - 1 ||
          c.swap_accepts.size() != c.swap_attempts.size())
        throw std::invalid_argument("wrong number of replicas");
      for (const json& jr : replicas) c.replicas.push_back(ReplicaFromJson(jr, d));
      s.chains.push_back(std::move(c));
    }

    const json& best = j.at("best");
    s.best.valid = best.at("valid").get<bool>();
    s.best.level = ReadInteger<int>(best.at("level"));
    s.best.psi = ReadNumbers(best.at("psi"));
    if (s.best.valid && int(s.best.psi.size()) != d) throw std::invalid_argument("best: wrong size");
    s.best.log_prior = ReadNumber(best.at("log_prior"));
    s.best.log_likelihood = ReadNumber(best.at("log_likelihood"));
    s.sampling_best = ReadNumber(j.at("sampling_best"));
    // Absent from checkpoints written before convergence-driven runs: those resume as runs
    // of a fixed count that has not measured convergence yet.
    if (const auto it = j.find("convergence"); it != j.end()) {
      s.ended_by = it->at("ended_by").get<std::string>();
      s.max_rhat = ReadNumber(it->at("max_rhat"));
      s.min_ess = ReadNumber(it->at("min_ess"));
    }

    const json& jr = j.at("refine");
    RefineState& r = s.refine;
    r.step = ReadInteger<int>(jr.at("step"));
    r.have_point = jr.at("have_point").get<bool>();
    r.psi = ReadNumbers(jr.at("psi"));
    r.log_prior = ReadNumber(jr.at("log_prior"));
    r.log_likelihood = ReadNumber(jr.at("log_likelihood"));
    r.gradient = ReadNumbers(jr.at("gradient"));
    r.candidate = ReadNumbers(jr.at("candidate"));
    r.step_scale = ReadNumber(jr.at("step_scale"));
    if (!jr.at("inverse_hessian").empty()) r.inverse_hessian = ReadMatrix(jr.at("inverse_hessian"), d);
    const json& settle = j.at("settle");
    s.settle_rounds = ReadInteger<int>(settle.at("rounds"));
    s.calibration = settle.at("calibration");
    if (!settle.at("laplace").empty()) s.laplace = ReadMatrix(settle.at("laplace"), d);
    if (settle.contains("mode")) s.mode = ReadNumbers(settle.at("mode"));
    if (!s.mode.empty() && int(s.mode.size()) != d) throw std::invalid_argument("settle: mode of the wrong size");
    if ((s.phase == Phase::Refining || s.phase == Phase::Settling || s.phase == Phase::Restarting) &&
        (int(r.candidate.size()) != d || r.inverse_hessian.rows() != d ||
         (r.have_point && (int(r.psi.size()) != d || int(r.gradient.size()) != d))))
      throw std::invalid_argument("refinement state of the wrong size");

    const json& rows = j.at("samples");
    const size_t n = rows.at("iteration").size();
    for (const char* column : {"chain", "level", "temperature", "accepted", "swapped",
                               "log_prior", "log_likelihood", "psi"})
      if (rows.at(column).size() != n) throw std::invalid_argument("samples: columns differ in length");
    if (!RowsPerIteration(rows.at("iteration"), s))
      throw std::invalid_argument("samples: not one row per chain per iteration");
    s.samples.reserve(n);
    for (size_t i = 0; i < n; ++i) {
      Sample row;
      row.iteration = ReadInteger<int>(rows["iteration"][i]);
      row.chain = ReadInteger<int>(rows["chain"][i]);
      if (row.chain < 0 || row.chain >= std::max(s.options.chains, s.PosteriorChains()))
        throw std::invalid_argument("samples: chain out of range");
      row.level = ReadInteger<int>(rows["level"][i]);
      row.temperature = ReadNumber(rows["temperature"][i]);
      row.accepted = rows["accepted"][i].get<bool>();
      row.swapped = rows["swapped"][i].get<bool>();
      row.log_prior = ReadNumber(rows["log_prior"][i]);
      row.log_likelihood = ReadNumber(rows["log_likelihood"][i]);
      row.psi = ReadPsi(rows["psi"][i], d);
      s.samples.push_back(std::move(row));
    }
    // A run with the ladder cannot go on without it: its draws would start again mid-run.
    if (s.options.evidence_rungs > 0) s.evidence = EvidenceFromJson(j.at("evidence"), s);
    return s;
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(std::string("checkpoint: ") + e.what());
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    throw std::invalid_argument(what.rfind("checkpoint: ", 0) == 0 ? what : "checkpoint: " + what);
  }
}

}  // namespace vkr::opt::detail
