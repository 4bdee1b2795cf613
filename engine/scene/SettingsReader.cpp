#include "engine/scene/SettingsReader.h"

#include "engine/scene/SceneJson.h"

namespace vkr {
namespace {

scene_detail::Reader ReaderFor(const std::string& file, const std::set<std::string>& overridden) {
  scene_detail::Reader r;
  r.file = file;
  r.overridden = &overridden;
  return r;  // no expression table: settings are numbers, never parameters
}

}  // namespace

SettingsReader::SettingsReader(const Scene& scene, const std::string& block)
    : file_(scene.file.string()), block_(block), json_(Json::object()) {
  for (const SceneOverride& o : scene.overrides) overridden_.insert(o.path);
  if (const auto it = scene.settings.find(block); it != scene.settings.end()) json_ = Json::parse(it->second);
  if (!json_.is_object()) Fail("", "expected an object");
}

const SettingsReader::Json* SettingsReader::Find(const char* key) const {
  const auto it = json_.find(key);
  return it == json_.end() ? nullptr : &*it;
}

void SettingsReader::CheckKeys(std::initializer_list<const char*> allowed) const {
  ReaderFor(file_, overridden_).CheckObject(json_, block_, allowed);
}

double SettingsReader::Number(const Json& j, const std::string& key) const {
  return ReaderFor(file_, overridden_).Number(j, Path(key));
}

long long SettingsReader::Integer(const Json& j, const std::string& key, long long lo, long long hi) const {
  return ReaderFor(file_, overridden_).Integer(j, Path(key), lo, hi);
}

std::string SettingsReader::String(const Json& j, const std::string& key) const {
  return ReaderFor(file_, overridden_).String(j, Path(key));
}

bool SettingsReader::Bool(const Json& j, const std::string& key) const {
  if (!j.is_boolean()) Fail(key, "expected true or false");
  return j.get<bool>();
}

bool SettingsReader::IsWord(const Json& j, const std::string& key, const char* word, const char* number) const {
  if (!j.is_string()) return false;
  if (j.get<std::string>() == word) return true;
  Fail(key, std::string("expected ") + number + " or \"" + word + "\", got '" + j.get<std::string>() + "'");
}

std::string SettingsReader::OneOf(const Json& j, const std::string& key, const char* what,
                                  std::initializer_list<const char*> words) const {
  const std::string value = String(j, key);
  std::string list;
  for (const char* w : words) {
    if (value == w) return value;
    list += (list.empty() ? "" : ", ") + std::string(w);
  }
  Fail(key, std::string("unknown ") + what + " '" + value + "' (" + list + ")");
}

void SettingsReader::Fail(const std::string& key, const std::string& problem) const {
  ReaderFor(file_, overridden_).Fail(key.empty() ? block_ : Path(key), problem);
}

std::string SettingNumber(double value) { return scene_detail::Num(value); }

}  // namespace vkr
