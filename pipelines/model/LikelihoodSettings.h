#pragma once
// The scene file's "likelihood" block, typed (docs/guide/SCENE_FORMAT.md, "likelihood"): which
// likelihood scores a hypothesis and how it is calibrated. One default per setting, here.

#include <string>

#include <nlohmann/json.hpp>

#include "engine/geometry/SceneGeometry.h"
#include "engine/scene/Scene.h"
#include "engine/scene/SettingsReader.h"
#include "pipelines/model/Photometric.h"

namespace vkr {

enum class LikelihoodKind { Surface, Image };  // pipelines/likelihood/SurfaceLikelihood.h, ImageLikelihood.h
const char* ToString(LikelihoodKind kind);
bool FromString(const std::string& text, LikelihoodKind* kind);

// How the surface likelihood weighs each view of a texel (§6.3): alike, or by the angle it is
// seen at.
enum class ViewWeights { Uniform, Angle };
const char* ToString(ViewWeights w);
bool FromString(const std::string& s, ViewWeights* w);

// Where the hypotheses of one submission write their depth maps, view layers and interior
// mask: one set shared by all (they run one after the other, ordered by barriers) or one
// set per hypothesis slot (memory × K; a GPU may then overlap the hypotheses of a batch).
// Auto: per slot on a GPU where it fits, shared on a CPU device. Results are the same to the
// bit either way.
enum class SlotImages { Auto, Shared, PerSlot };
const char* ToString(SlotImages s);
bool FromString(const std::string& s, SlotImages* out);

// How the image-space likelihood ranks a target camera's partners when only the best
// `partners` are compared.
enum class PartnerRanking {
  Distance,   // nearest camera centres first
  Direction,  // most similar viewing directions (optical axes) first
};
const char* ToString(PartnerRanking r);
bool FromString(const std::string& s, PartnerRanking* r);

// How the sandwich adjusts the log-likelihood (NoiseCalibration.h): Magnitude divides it by κ,
// the mean of H⁻¹J's eigenvalues, in every direction alike; Curvature gives each direction
// its own factor, so the posterior's covariance is the sandwich H⁻¹JH⁻¹.
enum class SandwichAdjustment { Magnitude, Curvature };
const char* ToString(SandwichAdjustment adjustment);
bool FromString(const std::string& text, SandwichAdjustment* adjustment);

// How κ is estimated at the mode when the scene does not fix it: Sandwich, by the block
// sandwich (NoiseCalibration.h); Noise, from the residuals' own correlation
// (NoiseCorrelation.h); Auto samples with the sandwich's and states the intervals at the
// noise's where the diagnosis finds no model error (recon/NoiseIntervals.h).
enum class KappaEstimate { Auto, Sandwich, Noise };
const char* ToString(KappaEstimate estimate);
bool FromString(const std::string& text, KappaEstimate* estimate);

struct LikelihoodSettings {
  LikelihoodKind kind = LikelihoodKind::Surface;
  // The noise sd on the 0–255 scale. With `sigma_auto` (`"sigma": "auto"`, the default) the
  // run estimates it from the data, and `sigma` is what a consumer that cannot estimate uses.
  bool sigma_auto = true;
  double sigma = 8.0;
  ViewWeights weights = ViewWeights::Angle;
  // Atlas side in texels and pyramid levels; 0 = "auto" (the default), sized from the cameras'
  // footprint of the surface by ResolveAutoLikelihood below.
  int atlas = 0;
  int levels = 0;
  ChartSizing charts = ChartSizing::Area;
  PhotometricModel photometric = PhotometricModel::Affine;  // per-camera colour correction
  SlotImages slot_images = SlotImages::Auto;
  // Mask what the photographs show that the scene leaves out, found at the mode a run settles
  // on (ClutterMasks.h).
  bool clutter = true;
  // The edge term (pipelines/model/EdgeEvidence.h): contours and creases on image edges.
  // On by default for the surface likelihood (LikelihoodSettingsFromJson); the image-space
  // likelihood has none.
  bool edges = true;
  // Texels per side of the blocks behind κ: 8, 16, 32 or 64; 0 ("auto") takes the largest κ
  // over those sizes.
  int sandwich_blocks = 0;
  SandwichAdjustment sandwich_adjustment = SandwichAdjustment::Magnitude;
  // κ, the factor the log-likelihood is divided by: a number fixes it, so that runs of
  // several scenes score one likelihood (`vkrecon compare`); 0 estimates it as
  // `kappa_estimate` says.
  double kappa = 0.0;
  KappaEstimate kappa_estimate = KappaEstimate::Auto;
  // δ in pixels, the noise's texture term (σ² + δ²|∇I|²): used as given with a fixed σ,
  // estimated with it under "auto".
  double position_sd = 0.5;
  // The image-space likelihood only: 0 compares every ordered camera pair; k > 0 each target
  // camera with its k best sources, ranked by `partner_ranking`.
  int partners = 0;
  PartnerRanking partner_ranking = PartnerRanking::Distance;

  // Whether every field is in range and the fields agree; otherwise `why` names the field
  // ("likelihood.atlas: …").
  bool IsValid(std::string* why) const;
};

// The block as map.json's `settings.likelihood` and a checkpoint state it: every field, words
// for enums and for "auto".
nlohmann::json ToJson(const LikelihoodSettings& settings);
// The block `reader` reads: the defaults above where it is silent. Throws InputError naming
// the scene file and the field (unknown key, wrong type, out of range); ToJson's output reads
// back as what it was written from.
LikelihoodSettings LikelihoodSettingsFromJson(const SettingsReader& block);
// The scene's block.
LikelihoodSettings LikelihoodSettingsOf(const Scene& scene);

// The scene's settings with "auto" (0) in atlas and levels replaced by the rule of
// engine/geometry/AtlasFootprint.h. Builds the meshes when the atlas is auto.
LikelihoodSettings ResolvedLikelihood(const Scene& scene);
// The same written into the scene's block, so every later reader of the scene (and map.json)
// sees the sizes used.
void ResolveAutoLikelihood(Scene& scene);

}  // namespace vkr
