#include "optimiser/Target.h"

#include <stdexcept>
#include <string>

namespace vkr::opt {

FunctionTarget::FunctionTarget(Function function, int max_batch, int levels)
    : function_(std::move(function)), max_batch_(max_batch), levels_(levels) {
  if (!function_ || max_batch < 1 || levels < 1)
    throw std::invalid_argument("FunctionTarget: needs a function, max_batch ≥ 1, levels ≥ 1");
}

void FunctionTarget::SetLevel(int level) {
  if (level < 0 || level >= levels_)
    throw std::logic_error("FunctionTarget::SetLevel: level " + std::to_string(level) +
                           " outside [0, " + std::to_string(levels_) + ")");
  level_ = level;
}

std::vector<double> FunctionTarget::Evaluate(const std::vector<std::vector<double>>& batch) {
  if (int(batch.size()) > max_batch_)
    throw std::logic_error("FunctionTarget::Evaluate: batch of " + std::to_string(batch.size()) +
                           " exceeds max_batch " + std::to_string(max_batch_));
  std::vector<double> out;
  out.reserve(batch.size());
  for (const std::vector<double>& psi : batch) out.push_back(function_(psi, level_));
  return out;
}

}  // namespace vkr::opt
