#include "pipelines/model/Evaluation.h"

#include <limits>

namespace vkr {

double Chi2PerDof(const ReducedScalars& scalars, double sigma_255) {
  const double sigma = sigma_255 / 255.0;
  return scalars.dof > 0 ? scalars.sum_squares / (sigma * sigma) / scalars.dof
                         : std::numeric_limits<double>::quiet_NaN();
}

Evaluation Score(const ReducedScalars& scalars, const LikelihoodModel& model) {
  const double sigma = model.sigma / 255.0;
  const double chi2 = scalars.sum_squares / (sigma * sigma);
  Evaluation e;
  e.scalars = scalars;
  // Without the correction a hypothesis that hides surface drops its texels' χ² terms and
  // looks better; subtracting each term's expectation (its dof) makes hidden, correctly
  // registered surface neutral (§7.4).
  e.log_likelihood = -0.5 * (model.chi2_correction ? chi2 - scalars.dof : chi2);
  e.log_occlusion_prior =
      -0.5 * (model.unseen_penalty * scalars.seen_none + model.unverified_penalty * scalars.unverified);
  return e;
}

}  // namespace vkr
