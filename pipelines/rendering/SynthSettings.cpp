#include "pipelines/rendering/SynthSettings.h"

namespace vkr {

bool SynthSettings::IsValid(std::string* why) const {
  const auto fail = [&](const char* text) {
    if (why) *why = text;
    return false;
  };
  if (!(sun_elevation > 0 && sun_elevation <= 90)) return fail("synth.sun[1]: elevation must be in (0, 90] degrees");
  if (!(ambient >= 0 && ambient <= 1)) return fail("synth.ambient: must be in [0, 1]");
  if (!(exposure >= 0 && exposure < 1)) return fail("synth.exposure: must be in [0, 1)");
  if (supersample < 1 || supersample > 8) return fail("synth.supersample: must be in [1, 8]");
  return true;
}

nlohmann::json ToJson(const SynthSettings& s) {
  nlohmann::json j = {{"ambient", s.ambient}, {"exposure", s.exposure}, {"supersample", s.supersample}};
  if (s.sun) j["sun"] = {s.sun_azimuth, s.sun_elevation};
  return j;
}

SynthSettings SynthSettingsFromJson(const SettingsReader& r) {
  r.CheckKeys({"sun", "ambient", "exposure", "supersample"});
  SynthSettings s;
  if (const auto* j = r.Find("sun")) {
    if (!j->is_array() || j->size() != 2) r.Fail("sun", "expected [azimuth, elevation] in degrees");
    s.sun = true;
    s.sun_azimuth = r.Number((*j)[0], "sun[0]");
    s.sun_elevation = r.Number((*j)[1], "sun[1]");
    if (!(s.sun_elevation > 0 && s.sun_elevation <= 90))
      r.Fail("sun[1]", "elevation " + SettingNumber(s.sun_elevation) + " must be in (0, 90] degrees");
  }
  if (const auto* j = r.Find("ambient")) {
    s.ambient = r.Number(*j, "ambient");
    if (!(s.ambient >= 0 && s.ambient <= 1)) r.Fail("ambient", "ambient " + SettingNumber(s.ambient) + " must be in [0, 1]");
  }
  if (const auto* j = r.Find("exposure")) {
    s.exposure = r.Number(*j, "exposure");
    if (!(s.exposure >= 0 && s.exposure < 1))
      r.Fail("exposure", "exposure spread " + SettingNumber(s.exposure) + " must be in [0, 1)");
  }
  if (const auto* j = r.Find("supersample")) s.supersample = int(r.Integer(*j, "supersample", 1, 8));
  return s;
}

SynthSettings SynthSettingsOf(const Scene& scene) { return SynthSettingsFromJson(SettingsReader(scene, "synth")); }

}  // namespace vkr
