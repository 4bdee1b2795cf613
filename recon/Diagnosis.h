#pragma once
// What the numbers at the MAP say about a reconstruction (docs/internals/LIKELIHOOD.md, "Diagnosis").
// A fit is called ok only on positive evidence: its residuals look like noise on every node
// and in every photograph, and the chains agree. Otherwise the diagnosis says which nodes or
// photographs disagree and by how much (model error: the scene leaves something out, or is
// wrong), or that the model does not explain the images at all (failed: `run` exits 1).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "recon/FinerAtlasPolish.h"
#include "engine/scene/Scene.h"
#include "optimiser/Sampler.h"
#include "pipelines/model/Evaluation.h"
#include "pipelines/rendering/ModelExport.h"
#include "pipelines/likelihood/Residuals.h"

namespace vkr::recon {

struct Diagnosis {
  enum class Verdict {
    Ok,            // residuals like noise everywhere, chains agree
    Unsettled,     // residuals like noise, but the chains disagree: run longer
    ModelError,    // a large share of some node's surface or photograph disagrees
    Failed,        // the model does not explain the images
    NotDiagnosed,  // the run stopped before its outputs: nothing was judged ("none")
  };
  Verdict verdict = Verdict::NotDiagnosed;
  std::vector<std::string> notes;  // one sentence each, most serious first
  nlohmann::json json;             // map.json's "diagnosis" (ok, verdict, notes, figures, nodes, cameras)

  bool ok() const { return verdict == Verdict::Ok; }
};
const char* ToString(Diagnosis::Verdict verdict);

// `sigma_255`: the noise σ the run ended with; `nodes`: NodeResiduals at the MAP (level 0);
// `reprojections`: the residuals of every photograph; `clutter_share`: per camera, the share
// of the pixels the model covers that were masked as clutter (empty: none masked);
// `finer`: the MAP's polish at twice the atlas's side (FinerAtlasPolish.h), or none.
Diagnosis Diagnose(const Scene& scene, const Evaluation& at_map, double sigma_255, const opt::SamplerSummary& summary,
                   const std::vector<NodeResidual>& nodes, const std::vector<Reprojection>& reprojections,
                   const std::vector<double>& clutter_share, const FinerAtlasPolish* finer = nullptr);

}  // namespace vkr::recon
