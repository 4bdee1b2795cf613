#include "recon/SceneList.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>

#include "engine/common/InputError.h"
#include "recon/Ranks.h"
#include "recon/SearchSetup.h"

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

namespace vkr::recon {

const char* ToString(ListedOutcome o) {
  switch (o) {
    case ListedOutcome::Ok: return "ok";
    case ListedOutcome::NotOk: return "not ok (see its map.json)";
    case ListedOutcome::ModelError: return "not trustworthy";
    case ListedOutcome::Interrupted: return "interrupted (--resume)";
    case ListedOutcome::BadInput: return "bad input";
    case ListedOutcome::Error: return "error";
  }
  return "?";
}

int ExitStatus(ListedOutcome o) {
  if (o == ListedOutcome::BadInput) return 2;
  return o == ListedOutcome::Ok || o == ListedOutcome::NotOk ? 0 : 1;
}

namespace {

// One scene of the list in this process; its notes and errors go to `log`.
ListedOutcome RunListed(const ListedScene& scene, const std::vector<SceneOverride>& overrides,
                        const ReconstructOptions& base, vk::Device& device, bool* stopped) {
  try {
    ReconstructOptions one = base;
    one.scene = std::make_shared<const Scene>(LoadSearchScene(scene.file, overrides));
    one.output_dir = base.output_dir / scene.name;
    one.ranks = nullptr;  // this process alone, while the job's other ranks run other scenes
    ReconstructSummary summary;
    Reconstruct(one, device, &summary);
    if (base.log)
      for (const std::string& note : summary.diagnosis.notes)
        *base.log << "vkrecon run: " << scene.name << ": note: " << note << "\n";
    if (!summary.completed()) {
      *stopped = true;
      return ListedOutcome::Interrupted;
    }
    if (summary.failed()) return ListedOutcome::ModelError;
    return summary.diagnosis.ok() ? ListedOutcome::Ok : ListedOutcome::NotOk;
  } catch (const InputError& e) {
    if (base.log) *base.log << "vkrecon run: " << e.what() << "\n";
    return ListedOutcome::BadInput;
  } catch (const std::exception& e) {
    if (base.log) *base.log << "vkrecon run: " << scene.name << ": error: " << e.what() << "\n";
    return ListedOutcome::Error;
  }
}

// Rank 0: the table of how every scene ended, on `log` and in OUT/summary.csv; the worst exit status.
int ReportList(const std::vector<ListedScene>& scenes, const std::vector<double>& all, const Ranks& ranks,
               const fs::path& out, std::ostream* log) {
  int worst = 0;
  const size_t n = scenes.size();
  fs::create_directories(out);
  std::ofstream csv(out / "summary.csv");
  csv << "scene,file,rank,exit_status,verdict,seconds,output\n";
  if (log) *log << "vkrecon run: " << n << " scene(s) on " << ranks.size() << " rank(s):\n";
  for (size_t i = 0; i < n; ++i) {
    const size_t owner = i % size_t(ranks.size());
    const auto outcome = ListedOutcome(int(all[owner * 2 * n + 2 * i]));
    const double seconds = all[owner * 2 * n + 2 * i + 1];
    const std::string folder = (out / scenes[i].name).string();
    worst = std::max(worst, ExitStatus(outcome));
    char line[512];
    std::snprintf(line, sizeof line, "  %-20s rank %-3zu exit %d  %7.1f s  %-26s %s\n", scenes[i].name.c_str(), owner,
                  ExitStatus(outcome), seconds, ToString(outcome), folder.c_str());
    if (log) *log << line;
    csv << scenes[i].name << "," << scenes[i].file.string() << "," << owner << "," << ExitStatus(outcome) << ","
        << ToString(outcome) << "," << seconds << "," << folder << "\n";
  }
  return worst;
}

}  // namespace

int ReconstructList(const std::vector<ListedScene>& scenes, const std::vector<SceneOverride>& overrides,
                    const ReconstructOptions& base, const Ranks& ranks, vk::Device& device) {
  ReconstructOptions options = base;
  options.quiet = base.quiet || ranks.distributed();  // one progress line per terminal
  const size_t n = scenes.size();
  std::vector<double> mine(2 * n, std::nan(""));  // per scene: outcome, seconds (travel to rank 0 as doubles)
  bool stopped = false;
  for (size_t i = 0; i < n; ++i) {
    if (int(i % size_t(ranks.size())) != ranks.rank()) continue;
    const auto start = std::chrono::steady_clock::now();
    const ListedOutcome outcome =
        stopped ? ListedOutcome::Interrupted : RunListed(scenes[i], overrides, options, device, &stopped);
    mine[2 * i] = double(outcome);
    mine[2 * i + 1] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  const std::vector<double> all = ranks.GatherToRoot(mine);
  if (ranks.rank() != 0) return 0;
  return ReportList(scenes, all, ranks, base.output_dir, base.log);
}

}  // namespace vkr::recon
