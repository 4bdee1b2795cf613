#include "recon/SceneList.h"

#include <algorithm>
#include <fstream>
#include <set>

#include "engine/common/InputError.h"

namespace vkr::recon {

namespace fs = std::filesystem;

bool IsSceneList(const fs::path& path) {
  return fs::is_directory(path) || path.extension() == ".txt" || path.extension() == ".list";
}

std::vector<ListedScene> ReadSceneList(const fs::path& path) {
  std::vector<ListedScene> scenes;
  if (fs::is_directory(path)) {
    for (const fs::directory_entry& entry : fs::directory_iterator(path))
      if (entry.is_directory() && fs::is_regular_file(entry.path() / "scene.json"))
        scenes.push_back({entry.path().filename().string(), entry.path() / "scene.json"});
    std::sort(scenes.begin(), scenes.end(), [](const ListedScene& a, const ListedScene& b) { return a.name < b.name; });
    if (scenes.empty()) throw InputError(path.string(), "", "no subfolder holds a scene.json: no scene to run");
    return scenes;
  }
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), "", "cannot read the list of scenes");
  std::set<std::string> names;
  int number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    const std::string field = "line " + std::to_string(number);
    line = line.substr(0, line.find('#'));
    line.erase(0, line.find_first_not_of(" \t\r"));
    line.erase(line.find_last_not_of(" \t\r") + 1);
    if (line.empty()) continue;
    fs::path file = fs::path(line).is_absolute() ? fs::path(line) : path.parent_path() / line;
    std::string name = file.stem().string();
    if (file.filename() == "scene.json") name = file.lexically_normal().parent_path().filename().string();
    if (fs::is_directory(file)) {
      name = fs::path(line).lexically_normal().filename().string();
      if (name.empty()) name = fs::path(line).lexically_normal().parent_path().filename().string();
      file /= "scene.json";
    }
    if (!fs::is_regular_file(file)) throw InputError(path.string(), field, "no scene file " + file.string());
    if (!names.insert(name).second)
      throw InputError(path.string(), field, "a second scene named '" + name + "': each needs its own output folder");
    scenes.push_back({name, file});
  }
  if (scenes.empty()) throw InputError(path.string(), "", "the list names no scene");
  return scenes;
}

}  // namespace vkr::recon
