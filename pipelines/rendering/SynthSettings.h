#pragma once
// The scene file's "synth" block, typed (docs/guide/SCENE_FORMAT.md, "synth"): how `vkrecon
// synth` renders the scene unless its command line says otherwise — reference images that
// look like photographs (a sun with cast shadows, exposure that differs between cameras,
// anti-aliasing). The defaults draw the albedo as it is.

#include <string>

#include <nlohmann/json.hpp>

#include "engine/scene/Scene.h"
#include "engine/scene/SettingsReader.h"

namespace vkr {

struct SynthSettings {
  bool sun = false;              // light the scene with a sun and ambient sky light
  double sun_azimuth = 135.0;    // degrees, from +x towards +y
  double sun_elevation = 50.0;   // degrees above the horizon, in (0, 90]
  double ambient = 0.3;          // share of the light that comes from the sky, on every face, in [0, 1]
  double exposure = 0.0;         // spread of each camera's exposure (gain ±spread, Exposure.h), in [0, 1)
  int supersample = 1;           // samples per pixel along each axis (anti-aliasing), 1 … 8

  // Whether every field is in range; otherwise `why` names the field ("synth.ambient: …").
  bool IsValid(std::string* why) const;
};

// The block as the scene file writes it ("sun" only when it is on).
nlohmann::json ToJson(const SynthSettings& settings);
// The block `reader` reads: the defaults above where it is silent; InputError naming the scene
// file and the field.
SynthSettings SynthSettingsFromJson(const SettingsReader& block);
SynthSettings SynthSettingsOf(const Scene& scene);

}  // namespace vkr
