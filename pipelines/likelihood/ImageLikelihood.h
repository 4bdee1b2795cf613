#pragma once
// The image-space photo-consistency likelihood (docs/internals/IMAGE_SPACE.md;
// thesis §4), assembled from passes: per camera a depth pass (DepthPass, shared with the surface
// likelihood), per target camera t a warp pass that renders the hypothesis from t, textures
// it with each source r_s through a shadow-map test from s (the synthetic images s_{s,t}) and
// writes per pixel the sum over sources of the χ² of r_t against them (TargetWarpPass, up to
// 8 sources per draw), and a reduction to the same ReducedScalars as the surface likelihood
// (ImageComparePass), scored by the same Score():
//
//   sum_squares = σ² Σ_{(s,t)} Σ_{pixels p of t seen by s} min(χ²_p, 3·cap)
//   dof         = 3 · seen_multi        (a pixel pair's χ² has 3 degrees of freedom)
//   seen_multi  = compared pixel pairs  (t sees the surface at p and s sees that point)
//   seen_once   = pixel pairs where t sees surface that s does not (occluded, outside, behind)
//   seen_none   = interior = 0          (image space only knows what some t sees, so it has
//                                        no occlusion prior: hidden surface is free)
//
// χ²_p = ‖r_t(p) − s_{s,t}(p)‖² / (σ² v_p), v_p = 1 + ν_s + b_t² + b_s²: a difference of two
// noisy samples has variance 2σ² per channel when both are raw pixels (ν_s = 1, b = 0); the
// sample of r_s is interpolated and prefiltered (ν_s < 1) and each image adds δ²|∇I|² for a
// projection uncertain by δ pixels (b = δ|∇I|/σ). docs/internals/IMAGE_SPACE.md has the details and
// the thesis's bias experiment.
//
// Everything is allocated when the likelihood is created (the per-pair images of a dump on
// the first dump). Evaluate() writes the batch's node matrices and cameras into host-visible
// buffers, records all K hypotheses × N targets into one command buffer, submits once, waits
// on one fence and reads back K small structs.

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/image/Image.h"
#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "pipelines/model/Evaluation.h"
#include "pipelines/model/LikelihoodSettings.h"

namespace vkr {

// An ordered camera pair: r_source is warped into target's view and compared with r_target.
struct CameraPair {
  int source = 0, target = 0;
  bool operator==(const CameraPair&) const = default;
};

// All ordered pairs (partners ≤ 0 or ≥ cameras − 1), else each target's `partners` best
// sources by `ranking` (ties: lower index first); grouped by target, targets in camera order.
std::vector<CameraPair> SelectPairs(const std::vector<Camera>& cameras, int partners, PartnerRanking ranking);

struct ImageLikelihoodOptions {
  // σ, the χ² correction (§7.4) and the robust cap; `unseen_penalty` has no effect here
  // (seen_none is always 0).
  LikelihoodModel model;
  // 0: compare every ordered pair (N(N−1) pixel pairs per pixel of the views); k > 0: each
  // target with its k best partners only (N·k). Scene: likelihood.partners and
  // likelihood.partner_ranking.
  int partners = 0;
  PartnerRanking ranking = PartnerRanking::Distance;
  int levels = 3;        // image pyramid levels built at creation
  int max_batch = 16;    // the most hypotheses one Evaluate() takes
  // Relative depth tolerance of the shadow-map test in s (a slope term is added).
  double depth_tolerance = 0.004;
  // δ of the noise model (Evaluation.h): how many pixels a projection may be off by.
  double position_sd = 0.5;
  bool profile = false;  // GPU timestamps around every pass (see LastPassTimesMs)

  bool IsValid(std::string* why) const;
  // Reads σ, levels, partners and their ranking from the scene's "likelihood" settings
  // (atlas and weights are the surface likelihood's and are ignored); max_batch keeps its
  // default. Throws InputError for more partners than a camera has.
  static ImageLikelihoodOptions FromScene(const Scene& scene);
};

// One pair of a dump (thesis Figs 4.5–4.8), at the level's image size of the target.
struct ImagePairDump {
  CameraPair pair;
  Image synthetic;    // s_{s,t}: rgb = r_s warped into t's view, a = 1 where compared
  Image consistency;  // r = χ² of the pixel pair, g = its dof (3 where compared), b = 0, a = 1 where t sees surface
};

struct ImageDump {
  std::vector<ImagePairDump> pairs;
};

class ImageLikelihood {
 public:
  // Loads every camera's image (which must exist and match its camera), builds pyramids and
  // uploads everything. Throws InputError for bad images, std::invalid_argument for bad options.
  ImageLikelihood(vk::Device& device, const Scene& scene, const ImageLikelihoodOptions& options);
  ~ImageLikelihood();
  ImageLikelihood(const ImageLikelihood&) = delete;
  ImageLikelihood& operator=(const ImageLikelihood&) = delete;

  // Pyramid level used by the next evaluations (0 = full resolution).
  void SetLevel(int level);
  // Noise σ (0–255 scale, > 0) of the next evaluations; `sigma: auto` runs estimate it.
  void SetSigma(double sigma_255);
  int level() const;
  int levels() const;

  // One evaluation per hypothesis; batch.size() ≤ max_batch.
  std::vector<Evaluation> Evaluate(const std::vector<std::vector<double>>& batch);

  // Evaluates one hypothesis and reads back every pair's synthetic and consistency images.
  ImageDump EvaluateAndDump(const std::vector<double>& psi, Evaluation* evaluation = nullptr);

  // With options.profile: GPU milliseconds per pass per hypothesis, averaged over the last
  // Evaluate() batch ("depth", "warp", "compare", "reduce").
  std::map<std::string, double> LastPassTimesMs() const;

  const std::vector<CameraPair>& pairs() const;
  const ImageLikelihoodOptions& options() const;
  const Scene& scene() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vkr
