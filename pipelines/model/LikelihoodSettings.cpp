#include "pipelines/model/LikelihoodSettings.h"

#include <climits>

#include "engine/geometry/AtlasFootprint.h"

namespace vkr {
namespace {

// `key`'s word as the enum T, or the defaults' value where the block is silent.
template <class T>
void ReadEnum(const SettingsReader& r, const char* key, const char* what,
              std::initializer_list<const char*> words, T* value) {
  if (const auto* j = r.Find(key)) FromString(r.OneOf(*j, key, what, words), value);
}

void ReadNoise(const SettingsReader& r, LikelihoodSettings& s) {
  if (const auto* j = r.Find("sigma")) {
    s.sigma_auto = j->is_string() && j->get<std::string>() == "auto";
    if (!s.sigma_auto) {
      s.sigma = r.Number(*j, "sigma");
      if (!(s.sigma > 0)) r.Fail("sigma", "sigma " + SettingNumber(s.sigma) + " must be > 0");
    }
  }
  if (const auto* j = r.Find("position_sd")) {
    s.position_sd = r.Number(*j, "position_sd");
    if (!(s.position_sd >= 0.0 && s.position_sd <= 10.0))
      r.Fail("position_sd", "position_sd " + SettingNumber(s.position_sd) + " must be in [0, 10] pixels");
  }
  if (const auto* j = r.Find("sandwich_blocks"); j && !r.IsWord(*j, "sandwich_blocks", "auto", "8, 16, 32 or 64")) {
    s.sandwich_blocks = int(r.Integer(*j, "sandwich_blocks", 8, 64));
    if (s.sandwich_blocks & (s.sandwich_blocks - 1))
      r.Fail("sandwich_blocks", "blocks of " + std::to_string(s.sandwich_blocks) +
                                    " texels: expected 8, 16, 32, 64 or \"auto\"");
  }
  ReadEnum(r, "sandwich_adjustment", "adjustment", {"magnitude", "curvature"}, &s.sandwich_adjustment);
  if (const auto* j = r.Find("kappa"); j && j->is_string() && (*j == "sandwich" || *j == "noise")) {
    FromString(j->get<std::string>(), &s.kappa_estimate);
  } else if (j && !r.IsWord(*j, "kappa", "auto", "a number, \"sandwich\", \"noise\"")) {
    s.kappa = r.Number(*j, "kappa");
    if (!(s.kappa > 0.0 && s.kappa < 1e9))
      r.Fail("kappa", "kappa " + SettingNumber(s.kappa) + " must be > 0 (or \"auto\", \"sandwich\", \"noise\")");
  }
}

void ReadAtlas(const SettingsReader& r, LikelihoodSettings& s) {
  if (const auto* j = r.Find("atlas"); j && !r.IsWord(*j, "atlas", "auto", "a power of two")) {
    s.atlas = int(r.Integer(*j, "atlas", 64, 8192));
    if (s.atlas & (s.atlas - 1)) r.Fail("atlas", "atlas " + std::to_string(s.atlas) + " is not a power of two");
  }
  if (const auto* j = r.Find("levels"); j && !r.IsWord(*j, "levels", "auto", "an integer"))
    s.levels = int(r.Integer(*j, "levels", 1, 8));
  ReadEnum(r, "charts", "chart sizing", {"area", "pixels"}, &s.charts);
}

}  // namespace

const char* ToString(ViewWeights w) { return w == ViewWeights::Uniform ? "uniform" : "angle"; }
bool FromString(const std::string& s, ViewWeights* w) {
  if (s == "uniform") *w = ViewWeights::Uniform;
  else if (s == "angle") *w = ViewWeights::Angle;
  else return false;
  return true;
}

const char* ToString(SlotImages s) {
  return s == SlotImages::Shared ? "shared" : s == SlotImages::PerSlot ? "per_slot" : "auto";
}
bool FromString(const std::string& s, SlotImages* out) {
  if (s == "auto") *out = SlotImages::Auto;
  else if (s == "shared") *out = SlotImages::Shared;
  else if (s == "per_slot") *out = SlotImages::PerSlot;
  else return false;
  return true;
}

const char* ToString(PartnerRanking r) { return r == PartnerRanking::Distance ? "distance" : "direction"; }
bool FromString(const std::string& s, PartnerRanking* r) {
  if (s == "distance") *r = PartnerRanking::Distance;
  else if (s == "direction") *r = PartnerRanking::Direction;
  else return false;
  return true;
}

const char* ToString(LikelihoodKind kind) { return kind == LikelihoodKind::Image ? "image" : "surface"; }
bool FromString(const std::string& text, LikelihoodKind* kind) {
  if (text == "surface") *kind = LikelihoodKind::Surface;
  else if (text == "image") *kind = LikelihoodKind::Image;
  else return false;
  return true;
}

const char* ToString(SandwichAdjustment a) { return a == SandwichAdjustment::Curvature ? "curvature" : "magnitude"; }
bool FromString(const std::string& text, SandwichAdjustment* a) {
  if (text == "magnitude") *a = SandwichAdjustment::Magnitude;
  else if (text == "curvature") *a = SandwichAdjustment::Curvature;
  else return false;
  return true;
}

const char* ToString(KappaEstimate e) {
  switch (e) {
    case KappaEstimate::Auto: return "auto";
    case KappaEstimate::Sandwich: return "sandwich";
    case KappaEstimate::Noise: return "noise";
  }
  return "?";
}
bool FromString(const std::string& text, KappaEstimate* e) {
  if (text == "auto") *e = KappaEstimate::Auto;
  else if (text == "sandwich") *e = KappaEstimate::Sandwich;
  else if (text == "noise") *e = KappaEstimate::Noise;
  else return false;
  return true;
}

bool LikelihoodSettings::IsValid(std::string* why) const {
  const auto fail = [&](const char* text) {
    if (why) *why = text;
    return false;
  };
  const auto power_of_two = [](int v) { return (v & (v - 1)) == 0; };
  if (!sigma_auto && !(sigma > 0.0)) return fail("likelihood.sigma: must be > 0");
  if (atlas != 0 && !(atlas >= 64 && atlas <= 8192 && power_of_two(atlas)))
    return fail("likelihood.atlas: must be a power of two in [64, 8192], or 0 (auto)");
  if (levels < 0 || levels > 8) return fail("likelihood.levels: must be in [1, 8], or 0 (auto)");
  if (sandwich_blocks != 0 && !(sandwich_blocks >= 8 && sandwich_blocks <= 64 && power_of_two(sandwich_blocks)))
    return fail("likelihood.sandwich_blocks: must be 8, 16, 32, 64 or 0 (auto)");
  if (!(kappa == 0.0 || (kappa > 0.0 && kappa < 1e9))) return fail("likelihood.kappa: must be > 0, or 0 (estimated)");
  if (!(position_sd >= 0.0 && position_sd <= 10.0)) return fail("likelihood.position_sd: must be in [0, 10] pixels");
  if (partners < 0) return fail("likelihood.partners: must be ≥ 0");
  if (edges && kind == LikelihoodKind::Image)
    return fail("likelihood.edges: the image-space likelihood has no edge term (the surface likelihood has)");
  return true;
}

nlohmann::json ToJson(const LikelihoodSettings& l) {
  using nlohmann::json;
  return {{"kind", ToString(l.kind)},
          {"sigma", l.sigma_auto ? json("auto") : json(l.sigma)},
          {"weights", ToString(l.weights)},
          {"atlas", l.atlas},
          {"levels", l.levels},
          {"charts", ToString(l.charts)},
          {"photometric", ToString(l.photometric)},
          {"clutter", l.clutter},
          {"edges", l.edges},
          {"sandwich_blocks", l.sandwich_blocks == 0 ? json("auto") : json(l.sandwich_blocks)},
          {"sandwich_adjustment", ToString(l.sandwich_adjustment)},
          {"kappa", l.kappa > 0.0 ? json(l.kappa) : json(ToString(l.kappa_estimate))},
          {"position_sd", l.position_sd},
          {"partners", l.partners},
          {"partner_ranking", ToString(l.partner_ranking)}};
}

LikelihoodSettings LikelihoodSettingsFromJson(const SettingsReader& r) {
  r.CheckKeys({"kind", "sigma", "weights", "atlas", "levels", "charts", "photometric", "clutter", "edges",
               "slot_images", "partners", "partner_ranking", "sandwich_blocks", "sandwich_adjustment", "kappa",
               "position_sd"});
  LikelihoodSettings s;
  ReadEnum(r, "kind", "kind", {"surface", "image"}, &s.kind);
  ReadEnum(r, "weights", "weights", {"uniform", "angle"}, &s.weights);
  ReadAtlas(r, s);
  ReadEnum(r, "slot_images", "value", {"auto", "shared", "per_slot"}, &s.slot_images);
  ReadEnum(r, "photometric", "photometric model", {"none", "gain", "affine"}, &s.photometric);
  if (const auto* j = r.Find("clutter")) s.clutter = r.Bool(*j, "clutter");
  // The edge term is on by default where there is one (the surface likelihood).
  s.edges = s.kind == LikelihoodKind::Surface;
  if (const auto* j = r.Find("edges")) s.edges = r.Bool(*j, "edges");
  ReadNoise(r, s);
  // Whether k exceeds the other cameras is checked where the cameras are known
  // (ImageLikelihoodOptions::FromScene).
  if (const auto* j = r.Find("partners")) s.partners = int(r.Integer(*j, "partners", 0, INT_MAX));
  ReadEnum(r, "partner_ranking", "ranking", {"distance", "direction"}, &s.partner_ranking);
  if (s.edges && s.kind == LikelihoodKind::Image)
    r.Fail("edges", "the image-space likelihood has no edge term (the surface likelihood has)");
  return s;
}

LikelihoodSettings LikelihoodSettingsOf(const Scene& scene) {
  return LikelihoodSettingsFromJson(SettingsReader(scene, "likelihood"));
}

LikelihoodSettings ResolvedLikelihood(const Scene& scene) {
  LikelihoodSettings s = LikelihoodSettingsOf(scene);
  if (s.atlas <= 0) s.atlas = AutoAtlasSide(SurfaceFootprintPixels(scene, BuildMeshes(scene)));
  if (s.levels <= 0) s.levels = AutoLevels(s.atlas);
  return s;
}

void ResolveAutoLikelihood(Scene& scene) {
  const LikelihoodSettings s = ResolvedLikelihood(scene);
  nlohmann::ordered_json block = SettingsReader(scene, "likelihood").json();
  block["atlas"] = s.atlas;
  block["levels"] = s.levels;
  scene.settings["likelihood"] = block.dump();
}

}  // namespace vkr
