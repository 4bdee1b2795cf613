#pragma once
// A scene file's settings blocks belong to the layers that use them: "likelihood" to
// LikelihoodSettings (pipelines/model/LikelihoodSettings.h), "synth" to SynthSettings
// (pipelines/rendering/SynthSettings.h), "sampler" to opt::SamplerOptions (optimiser/
// SamplerOptions.h; recon/SearchSetup.h's SamplerOptionsOf reads a scene's). The scene keeps
// each block as the file and its overrides wrote it (Scene::settings); a SettingsReader reads
// one, and its errors name the scene file and the field as the loader's do.

#include <initializer_list>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/scene/Scene.h"

namespace vkr {

class SettingsReader {
 public:
  using Json = nlohmann::ordered_json;

  // The scene's block named `block` ("likelihood", …); an empty object where the file has none.
  SettingsReader(const Scene& scene, const std::string& block);

  const Json& json() const { return json_; }
  // The value of `key`, or null where the block does not set it.
  const Json* Find(const char* key) const;
  // InputError for a key not in `allowed` (with a near miss suggested).
  void CheckKeys(std::initializer_list<const char*> allowed) const;

  // Typed values of `key`, whose value is `j`; InputError naming "block.key" otherwise.
  // Numbers may be written as constant expressions ("2 * 4"), as everywhere in a scene file.
  double Number(const Json& j, const std::string& key) const;
  long long Integer(const Json& j, const std::string& key, long long lo, long long hi) const;
  std::string String(const Json& j, const std::string& key) const;
  bool Bool(const Json& j, const std::string& key) const;
  // A field that takes a word instead of a number: whether `j` is that word; another string
  // fails naming what the field takes (`number`).
  bool IsWord(const Json& j, const std::string& key, const char* word, const char* number) const;
  // One of `words`; else InputError "unknown WHAT 'x' (a, b, c)".
  std::string OneOf(const Json& j, const std::string& key, const char* what,
                    std::initializer_list<const char*> words) const;

  [[noreturn]] void Fail(const std::string& key, const std::string& problem) const;
  std::string Path(const std::string& key) const { return block_ + "." + key; }

 private:
  std::string file_, block_;
  std::set<std::string> overridden_;
  Json json_;
};

// A number as a message shows it ("%g").
std::string SettingNumber(double value);

}  // namespace vkr
