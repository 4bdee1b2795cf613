#pragma once
// The MAP polished on the likelihood at twice the atlas's side (docs/internals/LIKELIHOOD.md, "The
// finer atlas").
//
// The surface likelihood compares the photographs through an atlas of a fixed size. Where a
// texel is larger than the pixels it covers, detail the photographs resolve (window frames,
// mortar, a box's edge) is averaged away and the mode sits off where a finer atlas puts it.
// On the bundled assets the mode at twice the side lay closer to the truth in nearly every
// parameter (box at σ 16: median error 0.07 → 0.01 % of the prior width; house_annex 1.84 →
// 0.96 %), and Merton's corner moved from xc −0.56 at 512² to −0.41 in a whole run at 1024².
// Sampling at the finer atlas costs four times as much per evaluation; climbing there from
// the MAP costs a few dozen evaluations.
//
// So after the polish `vkrecon run` builds the same likelihood at twice the atlas's side,
// calibrates its noise at the MAP (σ, colour correction and clutter masks, as a run at that
// atlas would; not κ), climbs from the MAP with BOBYQA, and that mode becomes the MAP; the
// posterior summaries move with it (AdoptPolishedMap). How far it moved, in the chains'
// posterior sds, is reported: beyond kFinerAtlasShiftSd the chains' intervals, even moved,
// describe the coarser likelihood rather than this mode, and the diagnosis says "unsettled".

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "optimiser/Sampler.h"

namespace vkr::recon {

// How far (posterior sds, any parameter) the MAP may move before the diagnosis says the
// intervals do not describe it. On the bundled assets the move was at most 1.19 sds (house
// at σ 16), on Merton at 512² 1.42 (docs/internals/LIKELIHOOD.md, "The finer atlas").
inline constexpr double kFinerAtlasShiftSd = 2.0;

// The largest atlas side polished at (twice the run's): above it the evaluations would cost
// as much as a run's.
inline constexpr int kFinerAtlasMaxSide = 2048;

struct FinerAtlasPolish {
  bool ran = false;
  std::string skipped;               // why not, when !ran ("" when off)
  int atlas = 0;                     // the doubled side
  double sigma = 0.0;                // the noise σ calibrated there
  std::vector<double> map;           // the mode found there: the run's MAP
  std::vector<double> map_at_atlas;  // the MAP before, at the run's atlas
  std::vector<double> shift_sd;      // per parameter: (map − map_at_atlas) / posterior sd
  int worst = -1;                    // index of the largest |shift_sd|
  int64_t evaluations = 0;           // at the doubled atlas (the calibration's few not counted)
  double seconds = 0.0;

  double MaxShiftSd() const { return worst >= 0 ? std::abs(shift_sd[size_t(worst)]) : 0.0; }
  bool Moved() const { return ran && MaxShiftSd() > kFinerAtlasShiftSd; }
};

// At most `evaluations` evaluations of BOBYQA at the doubled atlas (0: none), on `scene` read
// again from its file with the run's `overrides`, from summary.map. Needs the surface
// likelihood and a MAP; otherwise says why it skipped. `on_evaluate(n)`: after each
// evaluation of n hypotheses (each about four of the run's at level 0). Does not change
// `summary`: the caller adopts the map.
FinerAtlasPolish PolishAtFinerAtlas(vk::Device& device, const Scene& scene, std::vector<SceneOverride> overrides,
                                    const opt::SamplerSummary& summary, int evaluations, bool quiet,
                                    const std::function<void(size_t)>& on_evaluate = {});

// Makes the polished mode the run's MAP and moves each parameter's mean and 95 % interval by
// the MAP's move (ParameterSummary::interval_shift), within the prior's support and the
// parameter's bounds. The chains sampled the run's atlas, whose mode the atlas's averaging
// puts off the finer one's; their spread is the noise's, which the finer atlas keeps (κ
// scaled with the texels). So the posterior at the finer atlas is taken as theirs, moved:
// without it the MAP could lie outside its own interval (house_annex, stairs at σ 32:
// docs/internals/LIKELIHOOD.md, "The finer atlas"). Nothing when the polish did not run.
void AdoptPolishedMap(const FinerAtlasPolish& polish, const Scene& scene, opt::SamplerSummary* summary);

nlohmann::json ToJson(const FinerAtlasPolish& polish, const opt::SamplerSummary& summary);

// The diagnosis's sentence when the MAP moved beyond kFinerAtlasShiftSd ("" otherwise).
std::string FinerAtlasNote(const FinerAtlasPolish& polish, const opt::SamplerSummary& summary);

}  // namespace vkr::recon
