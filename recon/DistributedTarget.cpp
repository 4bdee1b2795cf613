#include "recon/DistributedTarget.h"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <limits>

namespace vkr::recon {
namespace {

double Since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

Slices SliceBatch(int n, int ranks) {
  Slices s;
  int offset = 0;
  for (int r = 0; r < ranks; ++r) {
    const int count = n / ranks + (r < n % ranks ? 1 : 0);
    s.counts.push_back(count);
    s.offsets.push_back(offset);
    offset += count;
  }
  return s;
}

std::vector<double> DistributedTarget::Evaluate(const std::vector<std::vector<double>>& batch) {
  if (!ranks_.distributed()) return local_.Evaluate(batch);
  const Slices slices = SliceBatch(int(batch.size()), ranks_.size());
  const int begin = slices.offsets[ranks_.rank()], count = slices.counts[ranks_.rank()];
  auto start = std::chrono::steady_clock::now();
  std::vector<double> mine;
  if (count > 0) {
    mine = local_.Evaluate(std::vector<std::vector<double>>(batch.begin() + begin, batch.begin() + begin + count));
    if (int(mine.size()) != count) throw std::logic_error("DistributedTarget: the target returned a wrong count");
  }
  times_.evaluate.push_back(Since(start));
  start = std::chrono::steady_clock::now();
  std::vector<double> all(batch.size());
  ranks_.AllGather(mine.data(), slices.counts, slices.offsets, all.data());
  times_.exchange.push_back(Since(start));
  return all;
}

nlohmann::json DistributedTarget::Calibrate(const std::vector<double>& psi, const std::vector<double>& covariance) {
  return AgreeWithRankZero(local_.Calibrate(psi, covariance));
}

nlohmann::json DistributedTarget::RefitAt(const std::vector<double>& psi) {
  return AgreeWithRankZero(local_.RefitAt(psi));
}

nlohmann::json DistributedTarget::AgreeWithRankZero(nlohmann::json mine) {
  if (!ranks_.distributed()) return mine;
  std::string text = ranks_.rank() == 0 ? mine.dump() : std::string();
  ranks_.Broadcast(&text);
  if (ranks_.rank() == 0) return mine;
  if (mine.dump() == text) return mine;
  std::cerr << "vkrecon run: warning: rank " << ranks_.rank()
            << " calibrated the noise model differently from rank 0 (different devices?); it takes rank 0's\n";
  nlohmann::json root = nlohmann::json::parse(text);
  local_.RestoreCalibration(root);
  return root;
}

std::vector<double> DistributedTarget::ScoreModes(const std::vector<std::vector<double>>& modes) {
  std::vector<double> scores = local_.ScoreModes(modes);
  if (ranks_.distributed())
    ranks_.Broadcast(reinterpret_cast<unsigned char*>(scores.data()), int(scores.size() * sizeof(double)));
  return scores;
}

nlohmann::json ExchangeCost(const ExchangeTimes& times, const Ranks& ranks, int batch) {
  const size_t calls = times.evaluate.size();
  std::vector<double> mine = times.evaluate;
  mine.insert(mine.end(), times.exchange.begin(), times.exchange.end());
  mine.push_back(times.control);
  const std::vector<double> all = ranks.GatherToRoot(mine);
  if (ranks.rank() != 0) return nullptr;
  const size_t stride = 2 * calls + 1;
  const int n = ranks.size();
  double evaluate = 0.0, exchange = 0.0, wait = 0.0, control = std::numeric_limits<double>::infinity();
  for (size_t c = 0; c < calls; ++c) {
    double slowest = 0.0, fastest_exchange = std::numeric_limits<double>::infinity(), sum_exchange = 0.0;
    for (int r = 0; r < n; ++r) {
      slowest = std::max(slowest, all[r * stride + c]);
      fastest_exchange = std::min(fastest_exchange, all[r * stride + calls + c]);
      sum_exchange += all[r * stride + calls + c];
    }
    evaluate += slowest;
    exchange += fastest_exchange;
    wait += sum_exchange / n - fastest_exchange;
  }
  for (int r = 0; r < n; ++r) control = std::min(control, all[r * stride + 2 * calls]);
  const double per = calls > 0 ? 1.0 / double(calls) : 0.0;
  const double control_per = times.control_messages > 0 ? control / times.control_messages : 0.0;
  // MPI_Allgatherv of `batch` doubles: every rank receives the others' (batch − its own)
  // values; with R ranks that is R(R − 1) point-to-point messages in the naive algorithm.
  return {{"ranks", n},
          {"calls", calls},
          {"frames", times.control_messages},
          {"evaluate_s", evaluate * per},
          {"exchange_s", exchange * per},
          {"wait_s", wait * per},
          {"control_s", control_per},
          {"bytes_per_call", 8 * batch},
          {"share", evaluate > 0 ? (exchange + control) / evaluate : 0.0}};
}

}  // namespace vkr::recon
