#pragma once
// Photometric differences between photographs (docs/internals/LIKELIHOOD.md, "Exposure and white
// balance"): auto-exposure, white balance and tone curves make the same surface look
// brighter or bluer in one photo than in another. The surface likelihood compares each
// camera's colours after a per-camera, per-channel correction c' = gain·c + offset, whose
// values are nuisance parameters fitted against the other cameras' consensus where the
// hypothesis puts surface — once before sampling and again at the mode a run settles on,
// like the noise σ. They describe the photographs, not the geometry, so a fit at any
// hypothesis that sees the scene roughly where it is serves all nearby ones; fitting once
// costs nothing per hypothesis, where a closed-form fit per hypothesis would cost a second
// pass over every view texture.

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "engine/image/Image.h"

namespace vkr {

// What the correction may change.
enum class PhotometricModel {
  None,    // compare the colours as stored
  Gain,    // a gain per camera and channel: exposure and white balance
  Affine,  // gain and offset per camera and channel: also black level, and a tone curve to first order
};
const char* ToString(PhotometricModel model);
bool FromString(const std::string& text, PhotometricModel* model);

struct PhotometricCorrection {
  std::vector<std::array<double, 3>> gain, offset;  // per camera, per channel

  static PhotometricCorrection Identity(int cameras);
  int cameras() const { return int(gain.size()); }
  bool IsIdentity() const;
};

nlohmann::json ToJson(const PhotometricCorrection& correction);
// Throws std::invalid_argument when malformed or for another number of cameras.
PhotometricCorrection PhotometricFromJson(const nlohmann::json& json, int cameras);

// Fits the correction from the view textures of one evaluation (per camera: rgb = the colour
// it saw, a = its weight, 0 where it does not see the texel; all of one size). Per camera and
// channel the corrected colours are matched to the consensus of the *other* cameras at the
// same texels: their mean for Gain (ratio of weighted means), their mean and spread for Affine
// (moment matching, which misregistration and noise bias far less than a regression slope).
// Views far from that consensus (beyond 4 robust sds) are left out, and the corrections are
// normalised to average gain 1 and offset 0, so colours keep the photographs' overall scale.
// Alternates a few rounds, since the consensus itself is corrected. A camera that shares fewer
// than `min_texels` texels with another keeps the identity.
PhotometricCorrection FitPhotometric(const std::vector<Image>& views, PhotometricModel model,
                                     int rounds = 4, int min_texels = 64);

}  // namespace vkr
