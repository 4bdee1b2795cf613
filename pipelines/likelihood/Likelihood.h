#pragma once
// What every likelihood offers its users (`vkrecon likelihood`, the sampler's target,
// `bench`), whatever its kind: the surface-space likelihood (§5–7) and the image-space one
// (§4) evaluate batches of hypotheses to the same reduced scalars (Evaluation.h), switch
// pyramid levels, dump their intermediate images and time their passes.
//
// The concrete classes need not derive from it: MakeLikelihood (LikelihoodTool.h) wraps each
// in a small adapter, so adding a kind is one branch there.

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/image/Image.h"
#include "pipelines/likelihood/ClutterMasks.h"
#include "pipelines/likelihood/NoiseCorrelation.h"
#include "pipelines/model/Evaluation.h"

namespace vkr {

// One image of a dump, and how a file should present it.
struct DumpImage {
  enum class Kind {
    Colour,     // encoded colour (a texture, a composite): EXR as linear light, like `render`
    Deviation,  // data: r = χ_t, g = d_t (dof), b = 1 on interior texels, a = 1 on surface
    Data,       // other numbers, stored as they are (no preview)
  };
  std::string name;  // file stem: "view_<camera>", "composite", "deviation", …
  Kind kind = Kind::Colour;
  bool preview = false;  // also worth an 8-bit PNG preview
  Image image;
};

// Everything one hypothesis's evaluation produced, for inspection (thesis Figs 5.9, 6.5, 7.25).
struct LikelihoodDump {
  std::vector<DumpImage> images;
};

class Likelihood {
 public:
  virtual ~Likelihood() = default;

  virtual std::string kind() const = 0;  // "surface" | "image"
  virtual const LikelihoodModel& model() const = 0;
  virtual int max_batch() const = 0;     // the most hypotheses one Evaluate() takes

  // Pyramid level of the next evaluations (0 = full resolution, < levels()).
  virtual void SetLevel(int level) = 0;
  virtual int level() const = 0;
  virtual int levels() const = 0;
  // Noise σ (0–255 scale) of the next evaluations: `sigma: auto` estimates it at the mode.
  virtual void SetSigma(double sigma_255) = 0;
  // δ (pixels) of the noise model's texture term (Evaluation.h), estimated with σ; the
  // image-space kind keeps its own.
  virtual void SetPositionSd(double pixels) { (void)pixels; }
  // Fits the per-camera colour correction (Photometric.h) at ψ, at the current level, and
  // scores with it from now on. Returns it as JSON; null when the likelihood has none (the
  // image-space kind, or `photometric: none`).
  virtual nlohmann::json CalibratePhotometric(const std::vector<double>& psi) {
    (void)psi;
    return nullptr;
  }
  // Puts back what CalibratePhotometric returned (a resumed run).
  virtual void RestorePhotometric(const nlohmann::json& correction) { (void)correction; }
  // Finds what the photographs show that the scene leaves out (ClutterMasks.h) at ψ, with
  // the current noise model and colour correction, and masks it from now on. Returns the
  // masks; none for a likelihood without them (the image-space kind).
  virtual ClutterMasks MaskClutter(const std::vector<double>& psi) {
    (void)psi;
    return {};
  }
  // Puts back masks MaskClutter returned (a resumed run).
  virtual void SetClutterMasks(const std::vector<Image>& masks) { (void)masks; }
  // Compares every pixel again but those the user masked.
  virtual void ClearClutterMasks() {}
  // How many times the log-likelihood counts each independent noise sample at ψ
  // (NoiseCorrelation.h), at level 0 with the current noise model, correction and masks;
  // κ = 1 for a likelihood whose dumps carry no view residuals (the image-space kind).
  virtual NoiseCorrelationEstimate NoiseCorrelation(const std::vector<double>& psi) {
    (void)psi;
    return {};
  }

  // One evaluation per hypothesis, in one GPU submission; batch.size() ≤ max_batch().
  virtual std::vector<Evaluation> Evaluate(const std::vector<std::vector<double>>& batch) = 0;
  // Evaluates one hypothesis and reads back its intermediate images.
  virtual LikelihoodDump EvaluateAndDump(const std::vector<double>& psi, Evaluation* evaluation) = 0;
  // With profiling on: GPU milliseconds per pass per hypothesis over the last Evaluate().
  virtual std::map<std::string, double> LastPassTimesMs() const = 0;
};

}  // namespace vkr
