#pragma once
// A scene's likelihood as the optimiser sees it (an opt::Target): `run` samples it
// (Reconstruct.h), `fit` searches its mode with NLopt (Fit.h), the peers benchmark does both
// (bench/peers/PeersBench.h). SearchSetup.h makes the likelihood it wraps.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/image/Image.h"
#include "engine/scene/Scene.h"
#include "optimiser/Target.h"
#include "pipelines/likelihood/Likelihood.h"
#include "pipelines/likelihood/NoiseCalibration.h"
#include "pipelines/model/LikelihoodSettings.h"

namespace vkr::recon {

// Where a checkpoint's clutter masks live, relative to the output folder. Each settling
// round may find other masks; a file named by its content is never overwritten with other
// masks, so a checkpoint always reloads exactly the masks it was written with, wherever a
// run is killed (a fixed name was overwritten by the next round before the checkpoint that
// named it was replaced, and a resumed run diverged).
inline constexpr const char* kCheckpointMasks = "checkpoint-clutter";

// Called after every Evaluate with the level it scored at and how many hypotheses: what the
// peers benchmark counts (full-resolution equivalents need the level).
using EvaluationHook = std::function<void(int level, size_t hypotheses)>;

// The optimiser's view of a likelihood: a batch of Ψ in, log likelihood + occlusion prior
// out, divided by the sandwich factor κ once a run has settled at the mode and calibrated the
// noise model there (NoiseCalibration.h; `fit` never calibrates: κ = 1).
class LikelihoodTarget : public opt::Target {
 public:
  // `output_dir`: where the clutter masks found at the mode are kept, in clutter/ (they are
  // images, so the calibration that checkpoints carry names their files, relative to it).
  // `writes_files` false (MPI ranks other than 0): names the masks' files, writes none.
  LikelihoodTarget(Likelihood& likelihood, const Scene& scene, bool estimate_sigma, bool mask_clutter,
                   std::filesystem::path output_dir, bool writes_files, EvaluationHook on_evaluate = {});
  int max_batch() const override { return likelihood_.max_batch(); }
  int levels() const override { return likelihood_.levels(); }
  void SetLevel(int level) override;
  std::vector<double> Evaluate(const std::vector<std::vector<double>>& batch) override;
  nlohmann::json Calibrate(const std::vector<double>& psi, const std::vector<double>& covariance) override;
  void RestoreCalibration(const nlohmann::json& calibration) override;
  // The colour correction, σ and δ and the clutter masks estimated anew at ψ, as a settling
  // round calibrates (κ kept).
  nlohmann::json RefitAt(const std::vector<double>& psi) override;
  // Once calibrated: each mode with its own colour correction, over the pixels that are not
  // clutter to every mode (those each mode's own calibration would mask, intersected), with
  // the calibration's σ, δ and κ; then the calibration is put back as it was.
  std::vector<double> ScoreModes(const std::vector<std::vector<double>>& modes) override;

 private:
  // Keeps `mask` for checkpoints; its file name relative to the output folder.
  std::string KeepMask(const std::string& camera, const Image& mask) const;
  // calibration_ as checkpoints and map.json carry it, its masks kept as files.
  nlohmann::json CalibrationJson() const;

  Likelihood& likelihood_;
  const Scene& scene_;
  const LikelihoodSettings settings_;  // the scene's "likelihood" block
  bool estimate_sigma_, mask_clutter_, writes_files_;
  std::filesystem::path output_dir_;
  EvaluationHook on_evaluate_;
  int level_ = 0;
  NoiseCalibration calibration_;  // κ = 1 until calibrated
  bool calibrated_ = false;
};

}  // namespace vkr::recon
