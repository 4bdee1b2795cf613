#include "recon/LikelihoodTarget.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>

#include "pipelines/likelihood/SandwichAdjustment.h"
#include "recon/AtomicWrite.h"

namespace fs = std::filesystem;

namespace vkr::recon {
namespace {

std::string MaskFileName(const std::string& camera, const Image& mask) {
  uint64_t hash = 1469598103934665603ull;  // FNV-1a over the pixels' bytes
  const auto* bytes = reinterpret_cast<const unsigned char*>(mask.rgba.data());
  for (size_t i = 0; i < mask.rgba.size() * sizeof(float); ++i) hash = (hash ^ bytes[i]) * 1099511628211ull;
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
  return std::string(kCheckpointMasks) + "/" + camera + "-" + hex + ".png";
}

}  // namespace

LikelihoodTarget::LikelihoodTarget(Likelihood& likelihood, const Scene& scene, bool estimate_sigma,
                                   bool mask_clutter, fs::path output_dir, bool writes_files,
                                   EvaluationHook on_evaluate)
    : likelihood_(likelihood),
      scene_(scene),
      settings_(LikelihoodSettingsOf(scene)),
      estimate_sigma_(estimate_sigma),
      mask_clutter_(mask_clutter),
      writes_files_(writes_files),
      output_dir_(std::move(output_dir)),
      on_evaluate_(std::move(on_evaluate)) {}

void LikelihoodTarget::SetLevel(int level) {
  likelihood_.SetLevel(level);
  level_ = level;
}

std::vector<double> LikelihoodTarget::Evaluate(const std::vector<std::vector<double>>& batch) {
  std::vector<double> out;
  const NoiseCalibration& c = calibration_;
  const std::vector<Evaluation> scored = likelihood_.Evaluate(batch);
  // The curvature adjustment is measured at full resolution; the coarse levels (the search's,
  // before any calibration) keep the magnitude adjustment.
  const bool adjusted = c.CurvatureAdjusted() && level_ == 0;
  for (size_t k = 0; k < scored.size(); ++k) {
    const double total = scored[k].total();
    out.push_back(adjusted ? c.centre_total / c.kappa +
                                 CurvatureRatio(c.adjusted_curvature, c.raw_curvature, c.adjustment_centre, batch[k]) *
                                     (total - c.centre_total)
                           : total / c.kappa);
  }
  if (on_evaluate_) on_evaluate_(level_, batch.size());
  return out;
}

nlohmann::json LikelihoodTarget::Calibrate(const std::vector<double>& psi, const std::vector<double>& covariance) {
  // The covariance is the target's: the raw log-likelihood's is κΣ under the magnitude
  // adjustment and Σ A H⁻¹ under the curvature adjustment (SandwichAdjustment.h).
  std::vector<double> raw = covariance;
  double kappa = calibration_.kappa;
  if (calibration_.CurvatureAdjusted()) {
    raw = RawInverseCurvature(covariance, calibration_.adjusted_curvature, calibration_.raw_curvature);
    kappa = 1.0;
  }
  const bool curvature = settings_.sandwich_adjustment == SandwichAdjustment::Curvature;
  calibration_ = CalibrateNoise(likelihood_, psi, raw, kappa, estimate_sigma_, mask_clutter_,
                                settings_.sandwich_blocks, 2.0, curvature);
  // A fixed `likelihood.kappa` replaces the estimate (kept only as kappa_min/max's report), so
  // that several scenes' evidences are of one likelihood (docs/guide/WHICH_SCENE.md).
  if (settings_.kappa > 0.0) calibration_.kappa = settings_.kappa;
  else if (settings_.kappa_estimate == KappaEstimate::Noise) calibration_.kappa = calibration_.kappa_noise;
  calibrated_ = true;
  return CalibrationJson();
}

nlohmann::json LikelihoodTarget::CalibrationJson() const {
  nlohmann::json json = ToJson(calibration_);
  const ClutterMasks& clutter = calibration_.clutter;
  if (!clutter.masks.empty()) {
    nlohmann::json files = nlohmann::json::array();
    for (size_t i = 0; i < clutter.masks.size(); ++i) files.push_back(KeepMask(scene_.cameras[i].name, clutter.masks[i]));
    json["clutter"] = {{"files", files}, {"share", clutter.share}};
  }
  return json;
}

nlohmann::json LikelihoodTarget::RefitAt(const std::vector<double>& psi) {
  if (!calibrated_) return nullptr;
  // A settling round's calibration at ψ without the sandwich: the masks are found with the
  // σ fitted before them, as there (masking under the final, smaller σ finds more clutter;
  // on stairs at σ 0 1.8 times as much). κ stays the one the chains sampled with.
  const NoiseCalibration sandwich = calibration_;  // the chains' κ and its eigenvalues
  calibration_ = CalibrateNoise(likelihood_, psi, {}, sandwich.kappa, estimate_sigma_, mask_clutter_,
                                settings_.sandwich_blocks);
  calibration_.kappa = sandwich.kappa;
  calibration_.kappa_noise = sandwich.kappa_noise;
  calibration_.noise_rings = sandwich.noise_rings;
  calibration_.kappa_min = sandwich.kappa_min;
  calibration_.kappa_max = sandwich.kappa_max;
  calibration_.blocks = sandwich.blocks;
  calibration_.block = sandwich.block;
  // The adjustment's shape too, centred where the round settled (its level there is new).
  calibration_.adjusted_curvature = sandwich.adjusted_curvature;
  calibration_.raw_curvature = sandwich.raw_curvature;
  if (sandwich.CurvatureAdjusted()) calibration_.adjustment_centre = psi;
  return CalibrationJson();
}

std::string LikelihoodTarget::KeepMask(const std::string& camera, const Image& mask) const {
  const std::string file = MaskFileName(camera, mask);
  if (!writes_files_) return file;
  fs::create_directories(output_dir_ / kCheckpointMasks);
  if (!fs::exists(output_dir_ / file)) WritePngAtomically(output_dir_ / file, mask);
  return file;
}

void LikelihoodTarget::RestoreCalibration(const nlohmann::json& calibration) {
  calibration_ = NoiseCalibrationFromJson(calibration);
  calibrated_ = true;
  likelihood_.SetSigma(calibration_.sigma);
  likelihood_.SetPositionSd(calibration_.position_sd);
  likelihood_.RestorePhotometric(calibration_.photometric);
  if (calibration.contains("clutter")) {
    std::vector<Image> masks;
    for (const auto& file : calibration["clutter"]["files"])
      masks.push_back(LoadImage(output_dir_ / file.get<std::string>()));
    likelihood_.SetClutterMasks(masks);
    calibration_.clutter.masks = std::move(masks);
    calibration_.clutter.share = calibration["clutter"]["share"].get<std::vector<double>>();
  }
}

std::vector<double> LikelihoodTarget::ScoreModes(const std::vector<std::vector<double>>& modes) {
  if (!calibrated_) return opt::Target::ScoreModes(modes);
  SetLevel(0);
  // Masks found at one mode cover what that mode fails to explain, which is the evidence
  // against it (on the peers bench's poster, seed 4, the chains settled 10 % of the prior
  // too low and masked the column's top; under those masks their mode outscored the local
  // search's, which was right). What every mode calls clutter is clutter whichever is right.
  if (mask_clutter_) {
    std::vector<Image> shared;  // rgb 1 = compare, 0 = clutter to every mode; none: no clutter
    for (size_t m = 0; m < modes.size(); ++m) {
      likelihood_.ClearClutterMasks();
      likelihood_.CalibratePhotometric(modes[m]);
      const ClutterMasks found = likelihood_.MaskClutter(modes[m]);
      if (m == 0) {
        shared = found.masks;
      } else if (found.masks.size() != shared.size()) {
        shared.clear();  // a mode without masks: nothing is clutter to every mode
      } else {
        for (size_t i = 0; i < shared.size(); ++i)
          for (size_t k = 0; k < shared[i].rgba.size() && k < found.masks[i].rgba.size(); ++k)
            shared[i].rgba[k] = std::max(shared[i].rgba[k], found.masks[i].rgba[k]);
      }
    }
    if (shared.empty())
      likelihood_.ClearClutterMasks();
    else
      likelihood_.SetClutterMasks(shared);
  }
  // The colour correction is fitted at the mode too (moment matching, not the likelihood's
  // own maximum), so a correction fitted at one mode favours it as well.
  std::vector<double> scores;
  for (const std::vector<double>& psi : modes) {
    likelihood_.CalibratePhotometric(psi);
    scores.push_back(likelihood_.Evaluate({psi}).at(0).total() / calibration_.kappa);
  }
  if (on_evaluate_) on_evaluate_(0, modes.size());
  likelihood_.RestorePhotometric(calibration_.photometric);
  if (mask_clutter_) {
    if (calibration_.clutter.masks.empty())
      likelihood_.ClearClutterMasks();
    else
      likelihood_.SetClutterMasks(calibration_.clutter.masks);
  }
  return scores;
}

}  // namespace vkr::recon
