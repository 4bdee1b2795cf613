// `--set PATH=VALUE` (docs/guide/SCENE_FORMAT.md, "Overrides"): overrides edit the parsed JSON
// before it is interpreted, so an overridden value passes exactly the checks a value in the file
// would, and a mistyped key is caught as an unknown key.

#include <cctype>
#include <charconv>
#include <filesystem>
#include <system_error>

#include "engine/common/InputError.h"
#include "engine/scene/SceneJson.h"

namespace vkr {
namespace scene_detail {
namespace {

// One step of a dotted path: an object key, or a list index.
struct Step {
  std::string key;
  long index = -1;  // >= 0: a list index
};

std::vector<Step> SplitPath(const std::string& path, const std::string& display) {
  auto fail = [&](const std::string& why) -> void {
    throw InputError(display, path, "bad --set path: " + why);
  };
  std::vector<Step> steps;
  size_t i = 0;
  if (path.empty()) fail("empty path");
  while (i < path.size()) {
    size_t end = path.find_first_of(".[]", i);
    if (end == std::string::npos) end = path.size();
    if (end == i) fail("empty key at character " + std::to_string(i + 1));
    steps.push_back({path.substr(i, end - i), -1});
    i = end;
    while (i < path.size() && path[i] == '[') {
      const size_t close = path.find(']', i);
      if (close == std::string::npos || close == i + 1) fail("unclosed or empty [index]");
      const std::string digits = path.substr(i + 1, close - i - 1);
      for (char c : digits)
        if (!std::isdigit(static_cast<unsigned char>(c))) fail("index [" + digits + "] is not a number");
      long index = 0;
      const auto parsed = std::from_chars(digits.data(), digits.data() + digits.size(), index);
      if (parsed.ec != std::errc()) fail("index [" + digits + "] is out of range");  // stol threw here (fuzz_scene_json)
      steps.push_back({"", index});
      i = close + 1;
    }
    if (i < path.size()) {
      if (path[i] != '.' || i + 1 == path.size()) fail("unexpected '" + path.substr(i, 1) + "'");
      ++i;
    }
  }
  return steps;
}

// nlohmann's serialiser checks UTF-8; its parser checks a file's strings, but a --set value
// taken as a plain string is never parsed.
bool IsUtf8(const std::string& text) {
  try {
    (void)Json(text).dump();
    return true;
  } catch (const Json::type_error&) {
    return false;
  }
}

}  // namespace

}  // namespace scene_detail

std::vector<SceneOverride> ParseOverrides(const std::vector<std::string>& sets) {
  std::vector<SceneOverride> out;
  for (const std::string& s : sets) {
    const size_t eq = s.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError("", "--set", "expected PATH=VALUE, got '" + s + "'");
    SceneOverride o{s.substr(0, eq), s.substr(eq + 1)};
    const std::string& key = o.path;
    const bool path_field = key == "images" || key == "cameras" || key == "masks" || key == "cameras.colmap" ||
                            key.ends_with(".albedo") || key.ends_with(".mesh");
    if (path_field && !o.value.empty() && o.value.front() != '{' && o.value.front() != '[' &&
        o.value.front() != '"' && std::filesystem::path(o.value).is_relative())
      o.value = std::filesystem::absolute(o.value).string();
    out.push_back(o);
  }
  return out;
}

namespace scene_detail {

std::set<std::string> ApplyOverrides(Json& root, const std::vector<SceneOverride>& overrides,
                                     const std::string& display) {
  std::set<std::string> paths;
  for (const SceneOverride& o : overrides) {
    // Invalid UTF-8 in the scene's JSON would make every later dump of it throw a JSON
    // error instead of an InputError (fuzz_scene_json found it in a message).
    if (!IsUtf8(o.path) || !IsUtf8(o.value))
      throw InputError(display, "--set", "'" + o.path + "' or its value is not valid UTF-8");
    const std::vector<Step> steps = SplitPath(o.path, display);
    Json* node = &root;
    std::string at;  // canonical path walked so far, for messages
    for (const Step& s : steps) {
      if (s.index < 0) {
        if (node->is_null()) *node = Json::object();  // create missing keys on the way
        if (!node->is_object())
          throw InputError(display, o.path,
                           "cannot apply --set: " + (at.empty() ? "the file" : at) +
                               " is not an object");
        node = &(*node)[s.key];
        at = Join(at, s.key);
      } else {
        if (!node->is_array() || size_t(s.index) >= node->size())
          throw InputError(display, o.path,
                           "cannot apply --set: " + at + " has no element [" +
                               std::to_string(s.index) + "]");
        node = &(*node)[size_t(s.index)];
        at = Index(at, size_t(s.index));
      }
    }
    // A value that parses as JSON is taken as JSON (numbers, lists, objects), anything else
    // as a string, so `--set likelihood.kind=image` needs no quotes.
    Json value = Json::parse(o.value, nullptr, /*allow_exceptions=*/false);
    if (value.is_discarded()) value = o.value;
    *node = std::move(value);
    paths.insert(at);
  }
  return paths;
}

}  // namespace scene_detail
}  // namespace vkr
