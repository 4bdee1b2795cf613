#pragma once
// The surface-space photo-consistency likelihood (docs/internals/LIKELIHOOD.md; thesis §5–7),
// assembled from passes: per camera a depth pass and a view-specific texture pass, one interior
// (occlusion) pass, a composite + deviation compute pass that also reduces per workgroup, and a
// final reduction to one ReducedScalars per hypothesis.
//
// Everything is allocated when the likelihood is created. Evaluate() writes the batch's
// node matrices into a host-visible buffer, records all K hypotheses into one command
// buffer, submits once, waits on one fence and reads back K small structs.

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/geometry/SceneGeometry.h"
#include "engine/image/Image.h"
#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "pipelines/model/EdgeEvidence.h"
#include "pipelines/model/Evaluation.h"
#include "pipelines/model/LikelihoodSettings.h"
#include "pipelines/model/Photometric.h"

namespace vkr {

struct SurfaceLikelihoodOptions {
  LikelihoodModel model;
  ViewWeights weights = ViewWeights::Angle;  // §6.3
  int atlas = 1024;       // atlas side at level 0 (coarser levels use atlas >> level)
  ChartSizing charts = ChartSizing::Area;  // how the atlas shares its texels among the faces
  int levels = 3;         // image pyramid levels built at creation
  int max_batch = 16;     // the most hypotheses one Evaluate() takes
  // Relative depth tolerance of the shadow-map visibility test (a slope term is added).
  double depth_tolerance = 0.004;
  // What the per-camera colour correction may change (Photometric.h); it is fitted by
  // CalibratePhotometric, the identity until then.
  PhotometricModel photometric = PhotometricModel::None;
  bool profile = false;   // GPU timestamps around every pass (see LastPassTimesMs)
  // Skip shading what a camera cannot see (ViewCulling.h). Off only to test that it changes
  // nothing.
  bool cull_views = true;
  SlotImages slot_images = SlotImages::Auto;
  // The edge term (EdgeEvidence.h): model contours and creases should lie on the
  // photographs' edges. Off: Evaluation::log_edges stays 0.
  bool edges = false;
  EdgeModel edge_model;

  bool IsValid(std::string* why) const;
  // Reads σ, weights, atlas, levels, charts, the photometric model and the edge term from the
  // scene's "likelihood" settings (LikelihoodSettings.h; "auto" resolved). max_batch keeps its
  // default: the caller's sampler decides it.
  static SurfaceLikelihoodOptions FromScene(const Scene& scene);
};

// The textures of one evaluation, for `vkrecon likelihood --dump` (thesis Figs 5.9, 6.5, 7.25).
struct SurfaceDump {
  std::vector<Image> view_textures;  // per camera: rgb = colour seen (as stored), a = weight
  // Per camera, the rest of what the composite reads (ViewTexel.h): r = |∇I| where it sampled
  // (the noise model's texture), g = the sample's pixel mass, a = weight.
  std::vector<Image> view_noise;
  Image composite;                   // rgb = consensus colour (corrected), a = number of views
  Image deviation;                   // r = χ_t, g = d_t, b = interior (1), a = 1 on surface
  Image noise;                       // r = texture share of the noise, g = outlier views, b = views, a = surface
  // With the edge term: per camera (row) and model edge (column), r = Σ w·log-ratio and
  // g = Σ w, the scored length in level pixels (EdgePass.h); empty without it.
  Image edges;
};

// `options` with slot_images Auto resolved for `device` (SlotImages).
SurfaceLikelihoodOptions ResolveSlotImages(const SurfaceLikelihoodOptions& options, const Scene& scene,
                                           const vk::Device& device);

class SurfaceLikelihood {
 public:
  // Loads every camera's image (which must exist and match its camera), builds pyramids and
  // uploads everything. Throws InputError for bad images, std::invalid_argument for bad options.
  SurfaceLikelihood(vk::Device& device, const Scene& scene, const SurfaceLikelihoodOptions& options);
  ~SurfaceLikelihood();
  SurfaceLikelihood(const SurfaceLikelihood&) = delete;
  SurfaceLikelihood& operator=(const SurfaceLikelihood&) = delete;

  // Pyramid level used by the next evaluations (0 = full resolution).
  void SetLevel(int level);
  // Noise σ (0–255 scale, > 0) of the next evaluations; `sigma: auto` runs estimate it.
  void SetSigma(double sigma_255);
  // δ (pixels, ≥ 0) of the noise model's texture term (Evaluation.h).
  void SetPositionSd(double pixels);
  // The per-camera colour correction of the next evaluations.
  void SetPhotometric(const PhotometricCorrection& correction);
  const PhotometricCorrection& photometric() const;
  // Per camera, pixels (0) the next evaluations ignore on top of the camera's own mask:
  // what the photograph shows that the scene leaves out (ClutterMasks.h). Each of the
  // camera's image size.
  void SetClutterMasks(const std::vector<Image>& masks);
  void ClearClutterMasks();
  int level() const;
  int levels() const;

  // One evaluation per hypothesis; batch.size() ≤ max_batch.
  std::vector<Evaluation> Evaluate(const std::vector<std::vector<double>>& batch);

  // Evaluates one hypothesis and reads back all its textures.
  SurfaceDump EvaluateAndDump(const std::vector<double>& psi, Evaluation* evaluation = nullptr);

  // With options.profile: GPU milliseconds per pass per hypothesis, averaged over the last
  // Evaluate() batch ("depth", "view_texture", "interior", "composite", "reduce").
  std::map<std::string, double> LastPassTimesMs() const;

  const SurfaceLikelihoodOptions& options() const;
  const Scene& scene() const;
  const SceneGeometry& geometry() const;  // the atlas layout of every evaluation

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vkr
