#include "recon/Diagnosis.h"

#include "pipelines/model/LikelihoodSettings.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "pipelines/likelihood/NoiseCalibration.h"
#include "recon/NoiseIntervals.h"

namespace vkr::recon {
namespace {

// A model textured with the composite that differs from the photographs by this RMS
// (0–255 scale) where it covers them explains nothing: camera noise is a few units, JPEG
// and lighting add ten or twenty. (σ itself cannot tell: it is the noise of prefiltered
// samples, which averages pixels — images of pure noise of sd 120 give σ ≈ 11.)
constexpr double kImplausibleRms = 48.0;

// Where noise alone leaves residuals. Under the noise model a view is an outlier (e² > K,
// 3 sds in every channel) about once in 10⁵; edges, resampling and anti-aliasing of
// correctly placed surface make it 0.5–3 % on the bundled assets at their truth
// (docs/internals/LIKELIHOOD.md, "Diagnosis"). A node or photograph beyond these disagrees.
constexpr double kOutlierShare = 0.08;     // of a node's view samples
constexpr double kNodeChi2PerDof = 1.6;    // a node's χ² against what noise alone gives
constexpr double kMinNodeShare = 0.01;     // nodes with fewer compared texels are not judged
constexpr double kRhat = 1.1;              // chains that disagree more have not converged
constexpr double kNearPriorEnd = 0.05;    // of a uniform prior's width: a MAP this close to an end
// Clutter masks (ClutterMasks.h) keep only regions of outliers, which noise alone does not
// make; a few pixels along silhouettes are still masked on the bundled assets at their truth.
constexpr double kClutterShare = 0.02;

std::string Format(const char* format, double a, double b = 0.0, double c = 0.0) {
  char buf[320];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  return buf;
}

double ReprojectionRms(const std::vector<Reprojection>& reprojections) {
  double squares = 0.0;
  int64_t pixels = 0;
  for (const Reprojection& r : reprojections) {
    squares += r.rms_255 * r.rms_255 * double(r.pixels);
    pixels += r.pixels;
  }
  return pixels ? std::sqrt(squares / double(pixels)) : 0.0;
}

void Worsen(Diagnosis* d, Diagnosis::Verdict v) {
  if (int(v) > int(d->verdict)) d->verdict = v;
}

}  // namespace

const char* ToString(Diagnosis::Verdict verdict) {
  switch (verdict) {
    case Diagnosis::Verdict::Ok: return "ok";
    case Diagnosis::Verdict::Unsettled: return "unsettled";
    case Diagnosis::Verdict::ModelError: return "model_error";
    case Diagnosis::Verdict::Failed: return "failed";
    case Diagnosis::Verdict::NotDiagnosed: return "none";
  }
  return "failed";
}

Diagnosis Diagnose(const Scene& scene, const Evaluation& at_map, double sigma_255, const opt::SamplerSummary& summary,
                   const std::vector<NodeResidual>& nodes, const std::vector<Reprojection>& reprojections,
                   const std::vector<double>& clutter_share, const FinerAtlasPolish* finer) {
  Diagnosis d;
  d.verdict = Diagnosis::Verdict::Ok;  // until a check finds worse
  std::vector<std::string> failed, model, other;
  const ReducedScalars& s = at_map.scalars;
  const double chi2 = Chi2PerDof(s, sigma_255);
  const double surface = double(s.seen_multi) + s.seen_once + s.seen_none;
  if (!(s.seen_multi > 0.05 * surface))
    failed.push_back("less than 5 % of the surface is seen by two cameras at the MAP: the images show little of the scene");
  if (!(chi2 < 4.0))
    failed.push_back(Format("the views disagree far beyond the noise at the MAP (chi2 per dof %.2f with sigma %.1f): "
                            "the model does not explain the images",
                            chi2, sigma_255));
  const double rms = ReprojectionRms(reprojections);
  if (!(rms < kImplausibleRms))
    failed.push_back(Format("the model textured with the composite differs from the photographs by RMS %.1f (0-255) "
                            "where it covers them, far beyond camera noise: the model does not explain the images",
                            rms));

  // Model error: which nodes and photographs disagree beyond the noise, and how much.
  const NodeResidual total = TotalResidual(nodes);
  nlohmann::json node_json = nlohmann::json::array();
  for (const NodeResidual& n : nodes) {
    const bool judged = n.compared >= kMinNodeShare * total.compared && n.compared > 0;
    const bool bad = judged && (n.OutlierShare() > kOutlierShare || n.Chi2PerDof() > kNodeChi2PerDof);
    node_json.push_back({{"node", n.node}, {"texels", n.texels}, {"compared", n.compared},
                         {"seen_once", n.seen_once}, {"seen_none", n.seen_none}, {"chi2_per_dof", n.Chi2PerDof()},
                         {"outlier_share", n.OutlierShare()}, {"disagrees", bad}});
    if (bad)
      model.push_back(n.node + Format(": %.0f %% of its views are outliers and its chi2 per dof is %.2f (noise alone: "
                                      "under 1 %% and 1): the scene leaves out or misplaces something there",
                                      100.0 * n.OutlierShare(), n.Chi2PerDof()));
  }
  nlohmann::json camera_json = nlohmann::json::array();
  for (size_t i = 0; i < reprojections.size(); ++i) {
    const Reprojection& r = reprojections[i];
    const double clutter = i < clutter_share.size() ? clutter_share[i] : 0.0;
    // A photograph disagrees where it shows regions the scene lacks (its clutter mask). The
    // share of its pixels beyond 3 robust sds is reported, not judged: the model textured
    // with the atlas lacks the photograph's finest detail, which makes the tails heavy
    // (about 10 % even where the fit is exact: crate_clutter, docs/internals/LIKELIHOOD.md).
    const bool bad = clutter > kClutterShare;
    camera_json.push_back({{"camera", r.camera}, {"rms_255", r.rms_255}, {"pixels", r.pixels},
                           {"outlier_share", r.outlier_share}, {"clutter_share", clutter},
                           {"residual_image", r.residual_file.filename().string()}, {"disagrees", bad}});
    if (bad)
      model.push_back("photograph " + r.camera +
                      Format(": %.0f %% of the pixels the model covers show something the scene leaves out (masked "
                             "as clutter, see clutter/",
                             100.0 * clutter) +
                      r.camera + ".png and reprojections/" + r.residual_file.filename().string() + ")");
  }
  if (total.views > 0 && total.OutlierShare() > kOutlierShare)
    model.insert(model.begin(), Format("%.0f %% of all view samples are outliers of the robust composite (noise alone: "
                                       "under 1 %%): a large share of the surface disagrees",
                                       100.0 * total.OutlierShare()));

  // The sds the run will state (recon/NoiseIntervals.h): the noise's where no model error.
  const Diagnosis::Verdict provisional = !failed.empty()  ? Diagnosis::Verdict::Failed
                                         : !model.empty() ? Diagnosis::Verdict::ModelError
                                                          : Diagnosis::Verdict::Ok;
  const double scale = ChooseNoiseIntervals(LikelihoodSettingsOf(scene), summary.calibration, provisional).scale;
  for (size_t i = 0; i < summary.parameters.size() && i < scene.parameters.size(); ++i) {
    const opt::ParameterSummary& p = summary.parameters[i];
    const Prior& prior = scene.parameters[i].prior;
    const bool uniform = prior.kind == Prior::Kind::Uniform;
    const double prior_sd = uniform ? (prior.b - prior.a) / std::sqrt(12.0) : prior.b;
    const double sd =
        p.sd * SpreadFactor(scale, p.sd, uniform ? std::numeric_limits<double>::infinity() : prior_sd, p.laplace_sd);
    if (sd > 0.5 * prior_sd)
      other.push_back(p.name + Format(" is barely constrained by the images (posterior sd %g against the prior's %g)",
                                      sd, prior_sd));
    // Pressed against a uniform prior's end, the MAP may be the prior's, not the photographs'
    // (Merton's roof pitches at one seed). A note, not a verdict: some ends are physical.
    if (uniform && std::min(p.map - prior.a, prior.b - p.map) < kNearPriorEnd * (prior.b - prior.a))
      other.push_back(p.name + Format("'s MAP %g lies at its prior's end [%g, %g]: the photographs may want a value "
                                      "beyond it; widen the prior, or model what pulls it there",
                                      p.map, prior.a, prior.b));
    if (p.rhat > kRhat) {
      other.push_back(p.name + Format(": the chains disagree (R-hat %.3f); run longer", p.rhat));
      Worsen(&d, Diagnosis::Verdict::Unsettled);
    }
  }
  // The local search's mode scored higher than the chains' MAP (SamplerOptions::start_search).
  // Inside their 95 % intervals it is their own mode, climbed further than their
  // finite-difference refinement did: nothing to say. Outside, it is a mode they missed, and
  // their intervals describe another one.
  if (summary.map_from_search) {
    std::vector<std::string> outside;
    for (const opt::ParameterSummary& p : summary.parameters)
      if (p.map < p.q025 || p.map > p.q975) outside.push_back(p.name);
    if (!outside.empty()) {
      std::string names;
      for (const std::string& n : outside) names += (names.empty() ? "" : ", ") + n;
      other.push_back("the MAP is the local search's mode, which scored higher than anything the chains found and "
                      "lies outside their 95 % intervals (" + names +
                      "): they explored another mode, so the intervals do not describe this one; run longer");
      Worsen(&d, Diagnosis::Verdict::Unsettled);
    }
  }
  // A convergence-driven run that something else ended: its chains may be fine by the
  // thresholds above, but not by the ones it was asked to meet.
  if (summary.ended_by == "time_limit" || summary.ended_by == "max_iterations") {
    const bool timed = summary.ended_by == "time_limit";
    other.push_back(std::string("sampling ended at the ") + (timed ? "time limit" : "iteration cap") +
                    Format(" after %.0f iterations, before every R-hat <= 1.01 and bulk-ESS >= 400 (largest R-hat "
                           "%.3f, smallest ESS %.0f): raise ",
                           summary.iterations, summary.max_rhat, summary.min_ess) +
                    (timed ? "--time-limit (sampler.time_limit)" : "sampler.max_iterations") + " for intervals to trust");
    Worsen(&d, Diagnosis::Verdict::Unsettled);
  }
  // The MAP moved far when polished at twice the atlas's side: the intervals describe a
  // likelihood that averages away detail the photographs resolve, not the mode it found.
  if (finer && finer->Moved()) {
    other.push_back(FinerAtlasNote(*finer, summary));
    Worsen(&d, Diagnosis::Verdict::Unsettled);
  }
  const nlohmann::json& calibration = summary.calibration;
  if (calibration.is_object() && calibration.contains("kappa_min") && calibration["kappa_min"].is_number()) {
    const double kappa_min = calibration["kappa_min"].get<double>();
    const double kappa = calibration.value("kappa", 1.0), kappa_max = calibration.value("kappa_max", kappa);
    const double dimension = double(std::max<size_t>(summary.parameters.size(), 1));
    // Still below once the calibration has settled (NoiseCalibration.h, optimiser/Settle.cpp):
    // the curvature is too large somewhere, and κ, the mean of the eigenvalues, too small —
    // unless one eigenvalue makes nearly all of it: then one ill-measured direction widens
    // every interval towards its prior (Merton's corner at one seed: 648,256 of 7 × 93,047).
    if (kappa_min < kMinSandwichEigenvalue) {
      const bool one_direction = dimension >= 2.0 && kappa_max >= 0.9 * dimension * kappa;
      other.push_back(one_direction
          ? Format("the curvature measured at the mode is doubtful (the sandwich's eigenvalues run from %.2f to %.0f, "
                   "and the largest alone makes most of kappa = %.0f): the intervals may be far too wide; run again "
                   "with another sampler.seed", kappa_min, kappa_max, kappa)
          : Format("the curvature measured at the mode is doubtful (the sandwich's smallest eigenvalue is "
                   "%.2f, below 1): kappa may be too small and the intervals too narrow; run again with "
                   "another sampler.seed", kappa_min));
      Worsen(&d, Diagnosis::Verdict::Unsettled);
    }
  }
  if (!model.empty()) {
    Worsen(&d, Diagnosis::Verdict::ModelError);
    // κ over blocks of a fixed size (8×8 above all) measures the noise, not a bias that what
    // the scene leaves out gives the mode (docs/internals/LIKELIHOOD.md, "Honest intervals"): say so,
    // and what widens them.
    if (LikelihoodSettingsOf(scene).sandwich_blocks != 0)
      model.push_back("the intervals allow for the photographs' noise, not for what the scene leaves out, which can "
                      "move the MAP beyond them: model it, or set likelihood.sandwich_blocks to \"auto\" for "
                      "intervals that err wide (docs/internals/LIKELIHOOD.md, \"Honest intervals\")");
  }
  if (!failed.empty()) Worsen(&d, Diagnosis::Verdict::Failed);
  for (const auto* list : {&failed, &model, &other}) d.notes.insert(d.notes.end(), list->begin(), list->end());
  d.json = {{"ok", d.ok()},
            {"verdict", ToString(d.verdict)},
            {"notes", d.notes},
            {"chi2_per_dof", s.dof > 0 ? chi2 : 0.0},
            {"reprojection_rms", rms},
            {"outlier_share", total.OutlierShare()},
            {"seen_once_share", surface > 0 ? s.seen_once / surface : 0.0},
            {"nodes", node_json},
            {"cameras", camera_json}};
  return d;
}

}  // namespace vkr::recon
