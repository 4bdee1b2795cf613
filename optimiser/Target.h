#pragma once
// What the sampler samples: a function from a batch of hypotheses Ψ (each a vector in the
// order of the ParameterSpec list) to their log-likelihoods. The GPU likelihoods of
// pipelines/ are wrapped in one by recon/ (LikelihoodTarget.h); tests use FunctionTarget.

#include <cstdint>
#include <functional>
#include <vector>

#include <nlohmann/json.hpp>

namespace vkr::opt {

class Target {
 public:
  virtual ~Target() = default;

  // The most hypotheses one Evaluate() takes (K). The sampler never passes more.
  virtual int max_batch() const = 0;
  // Resolution levels (pyramid levels): 0 is the finest and the one the posterior is
  // defined at; coarser levels (§7.3) smooth the likelihood for the early iterations.
  virtual int levels() const { return 1; }
  // Level of the following evaluations, in [0, levels()).
  virtual void SetLevel(int level) { (void)level; }

  // One log-likelihood per hypothesis (without the prior). NaN or ±∞ marks a hypothesis
  // that cannot be scored: the sampler rejects it. Must return batch.size() values.
  virtual std::vector<double> Evaluate(const std::vector<std::vector<double>>& batch) = 0;

  // Nuisance parameters of the likelihood — its noise level, how much evidence its samples
  // really carry — estimated at ψ, the mode the sampler found once the exploration is over;
  // `covariance` (d × d, row-major) is the inverse curvature of the log posterior measured
  // there, as the target scored so far (after an earlier calibration, with it; not capped
  // by the prior). Afterwards Evaluate() scores with them. Returns what was estimated (kept
  // in checkpoints and map.json), null when the target has nothing to estimate;
  // RestoreCalibration puts a returned value back when a run resumes. While a returned
  // object's "kappa" moves, the sampler measures the curvature again and calls Calibrate
  // once more (at most four times per settling round).
  virtual nlohmann::json Calibrate(const std::vector<double>& psi, const std::vector<double>& covariance) {
    (void)psi;
    (void)covariance;
    return nullptr;
  }
  virtual void RestoreCalibration(const nlohmann::json& calibration) { (void)calibration; }

  // After another mode than the calibrated one became the MAP (a local search's, Polish.h's
  // AdoptIfHigher): what a calibration estimates at its mode — a colour correction, the
  // noise level, masks over what that mode fails to explain — estimated again at ψ, except
  // how much evidence the samples carry (κ, which the chains sampled with), so that what
  // follows (the polish, the outputs) describes ψ rather than the mode the chains
  // calibrated at. Returns the calibration as Calibrate() does; null where the target has
  // none (and is then unchanged). RestoreCalibration puts the earlier one back.
  virtual nlohmann::json RefitAt(const std::vector<double>& psi) {
    (void)psi;
    return nullptr;
  }

  // The log-likelihoods of competing modes (the chains' MAP, a local search's mode) at level
  // 0, scored so that no mode is favoured by where the calibration was made: a target whose
  // calibration fits nuisances at one mode (a colour correction, masks over what that mode
  // fails to explain) refits them for each mode here and leaves Evaluate() as it was. The
  // values compare with one another, not with Evaluate()'s. By default: Evaluate() at level 0.
  virtual std::vector<double> ScoreModes(const std::vector<std::vector<double>>& modes) {
    SetLevel(0);
    std::vector<double> scores;
    for (const std::vector<double>& psi : modes) scores.push_back(Evaluate({psi}).at(0));
    return scores;
  }
};

// A target from a plain function of (Ψ, level), evaluated one hypothesis at a time.
class FunctionTarget : public Target {
 public:
  using Function = std::function<double(const std::vector<double>& psi, int level)>;
  FunctionTarget(Function function, int max_batch, int levels = 1);

  int max_batch() const override { return max_batch_; }
  int levels() const override { return levels_; }
  void SetLevel(int level) override;
  int level() const { return level_; }
  // Throws std::logic_error for a batch larger than max_batch.
  std::vector<double> Evaluate(const std::vector<std::vector<double>>& batch) override;

 private:
  Function function_;
  int max_batch_ = 1;
  int levels_ = 1;
  int level_ = 0;
};

}  // namespace vkr::opt
