#pragma once
// A target spread over the run's ranks (docs/guide/SCALE_OUT.md): every rank holds the same
// sampler, so every rank asks for the same batch; each scores only its contiguous slice of
// it on its own device, and one MPI_Allgatherv gives every rank all the values, so all
// samplers advance identically and replica exchange needs no message of its own. With one
// rank it is the wrapped target, call for call.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "recon/Ranks.h"
#include "optimiser/Target.h"

namespace vkr::recon {

// The slices of a batch of n hypotheses over `ranks` ranks: contiguous, in the batch's order,
// sizes differing by at most one (the first n mod ranks get one more). Each hypothesis is
// scored on its own in the likelihood, so where a slot lies does not change its value
// (tested in cli/ScaleOut…); balance is all that matters.
struct Slices {
  std::vector<int> counts, offsets;
};
Slices SliceBatch(int n, int ranks);

// Time spent per Evaluate call, on this rank (seconds).
struct ExchangeTimes {
  std::vector<double> evaluate;  // scoring this rank's slice
  std::vector<double> exchange;  // in MPI_Allgatherv (waiting for the slowest rank included)
  double control = 0.0;          // in the per-frame broadcasts of the frame request
  int control_messages = 0;
};

class DistributedTarget : public opt::Target {
 public:
  // `local` scores hypotheses on this rank's device; it must be the same target, set up the
  // same way, on every rank.
  DistributedTarget(opt::Target& local, const Ranks& ranks) : local_(local), ranks_(ranks) {}

  int max_batch() const override { return local_.max_batch(); }
  int levels() const override { return local_.levels(); }
  void SetLevel(int level) override { local_.SetLevel(level); }
  std::vector<double> Evaluate(const std::vector<std::vector<double>>& batch) override;
  // Every rank calibrates (the same computation, so the same state as one process would
  // have); rank 0's result is broadcast and is what every sampler keeps. A rank whose own
  // result differs (a different GPU model rounds differently) takes rank 0's instead, with
  // a warning: its clutter masks are then read from the files rank 0 wrote into OUT.
  nlohmann::json Calibrate(const std::vector<double>& psi, const std::vector<double>& covariance) override;
  void RestoreCalibration(const nlohmann::json& calibration) override { local_.RestoreCalibration(calibration); }
  // As Calibrate: every rank refits, rank 0's result is what every rank keeps.
  nlohmann::json RefitAt(const std::vector<double>& psi) override;
  // Every rank scores the modes on its own device (the same computation, which leaves each
  // rank's likelihood as it was); rank 0's values, sent bit for bit, decide on every rank.
  std::vector<double> ScoreModes(const std::vector<std::vector<double>>& modes) override;

  ExchangeTimes& times() { return times_; }

 private:
  // `mine`, this rank's calibration, or rank 0's where they differ (with a warning).
  nlohmann::json AgreeWithRankZero(nlohmann::json mine);

  opt::Target& local_;
  const Ranks& ranks_;
  ExchangeTimes times_;
};

// The cost of the exchange over a run, from every rank's ExchangeTimes (call on every rank;
// collective). On rank 0: {"ranks", "calls", "evaluate_s" (per call, the slowest rank's),
// "exchange_s" (per call, the rank that arrived last: pure transfer and latency),
// "wait_s" (per call, mean over ranks of the rest: load imbalance), "control_s" (per frame
// request), "bytes_per_call", "messages_per_call", "share" (exchange / evaluate)}; null elsewhere.
nlohmann::json ExchangeCost(const ExchangeTimes& times, const Ranks& ranks, int batch);

}  // namespace vkr::recon
