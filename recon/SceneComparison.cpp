// `vkrecon compare`'s runs (SceneComparison.h): what each input is, the common likelihood
// calibration, the runs through the scene list (so MPI ranks share them), and the table.

#include "recon/SceneComparison.h"

#include <fstream>
#include <iomanip>
#include <optional>
#include <set>
#include <sstream>

#include "engine/common/InputError.h"
#include "recon/AtomicWrite.h"
#include "recon/Ranks.h"
#include "recon/SceneList.h"
#include "recon/SearchSetup.h"

namespace fs = std::filesystem;

namespace vkr::recon {
namespace {

// One input of the command line: a scene to run, or a finished run to read.
struct CompareInput {
  std::string name;
  fs::path scene_file;  // to run (empty for a finished run)
  fs::path run_folder;  // a finished run's folder (empty for a scene to run)
};

std::vector<CompareInput> ResolveInputs(const std::vector<fs::path>& paths) {
  std::vector<CompareInput> inputs;
  std::set<std::string> names;
  for (const fs::path& path : paths) {
    CompareInput in;
    const fs::path folder = path.lexically_normal().filename().empty() ? path.lexically_normal().parent_path()
                                                                        : path.lexically_normal();
    if (fs::is_directory(path) && fs::is_regular_file(path / "map.json")) {
      in = {folder.filename().string(), {}, path};
    } else if (fs::is_directory(path) && fs::is_regular_file(path / "scene.json")) {
      in = {folder.filename().string(), path / "scene.json", {}};
    } else if (fs::is_regular_file(path)) {
      const bool named_scene = path.filename() == "scene.json";
      in = {named_scene ? fs::absolute(path).parent_path().filename().string() : path.stem().string(), path, {}};
    } else {
      throw InputError(path.string(), "", "no such scene file, scene folder or finished run's folder (map.json)");
    }
    if (!names.insert(in.name).second)
      throw InputError(path.string(), "", "a second scene named '" + in.name + "': each needs its own folder under OUT");
    inputs.push_back(std::move(in));
  }
  if (inputs.size() < 2) throw InputError("", "compare", "give at least two scenes to compare");
  return inputs;
}

// A finished run's scene as it ran (map.json's settings), to check its photographs; null when
// its scene file is gone.
std::optional<Scene> SceneOfRun(const fs::path& run_folder) {
  std::ifstream in(run_folder / "map.json");
  const nlohmann::json map = nlohmann::json::parse(in, nullptr, false);
  if (map.is_discarded() || !map.contains("settings")) return std::nullopt;
  const fs::path file = map["settings"].value("scene", "");
  if (file.empty() || !fs::is_regular_file(file)) return std::nullopt;
  std::vector<std::string> sets = map["settings"].value("overrides", std::vector<std::string>{});
  return LoadSearchScene(file, ParseOverrides(sets));
}

std::string Exact(double x) {
  std::ostringstream o;
  o.imbue(std::locale::classic());
  o << std::setprecision(17) << x;
  return o.str();
}

// The overrides that fix the likelihood a finished run's evidence is of (its evidence.likelihood).
std::vector<SceneOverride> FixedLikelihood(const nlohmann::json& likelihood, const fs::path& map_file) {
  for (const char* key : {"sigma", "position_sd", "kappa"})
    if (!likelihood.is_object() || !likelihood.contains(key) || !likelihood[key].is_number())
      throw InputError(map_file.string(), std::string("evidence.likelihood.") + key,
                       "missing: the run does not say which likelihood its evidence is of");
  return {{"likelihood.sigma", Exact(likelihood["sigma"].get<double>())},
          {"likelihood.position_sd", Exact(likelihood["position_sd"].get<double>())},
          {"likelihood.kappa", Exact(likelihood["kappa"].get<double>())}};
}

// Rank 0's map.json text of a run, on every rank.
std::string ReadWhole(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// ReconstructList writes OUT/summary.csv for the scenes of its call: the reference's row, from
// the first call, goes back before the others' (`reference`: that first file, or empty).
void KeepReferenceRow(const fs::path& summary, const std::string& reference) {
  if (reference.empty()) return;
  std::string later = ReadWhole(summary);
  const size_t header = later.find('\n');
  later = header == std::string::npos ? std::string() : later.substr(header + 1);
  WriteAtomically(summary, reference + later);
}

nlohmann::json ReadOnRoot(const fs::path& run_folder, const Ranks& ranks) {
  std::string text;
  if (ranks.rank() == 0) {
    std::ifstream in(run_folder / "map.json");
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  ranks.Broadcast(&text);
  const nlohmann::json map = nlohmann::json::parse(text, nullptr, false);
  if (map.is_discarded() || !map.contains("evidence"))
    throw InputError((run_folder / "map.json").string(), "evidence",
                     "missing: the run recorded no evidence (run without sampler.evidence_rungs, or too few "
                     "iterations to record the ladder)");
  return map;
}

// Every input's scene loads (bad input ends the command before any run) and sees the same
// photographs; the scenes to run, in order. `finished`: the first finished run, if any.
std::vector<ListedScene> LoadAndCheck(const std::vector<CompareInput>& inputs,
                                      const std::vector<SceneOverride>& overrides, std::ostream* log,
                                      const CompareInput** finished) {
  std::vector<ListedScene> to_run;
  std::optional<Scene> first;
  for (const CompareInput& in : inputs) {
    std::optional<Scene> scene;
    if (!in.scene_file.empty()) {
      scene = LoadSearchScene(in.scene_file, overrides);
      to_run.push_back({in.name, in.scene_file});
    } else {
      if (!*finished) *finished = &in;
      scene = SceneOfRun(in.run_folder);
      if (!scene && log) *log << "vkrecon compare: " << in.name << ": its scene file is gone: photographs not checked\n";
    }
    if (scene && first) CheckSamePhotographs(*first, *scene);
    if (scene && !first) first = std::move(scene);
  }
  return to_run;
}

// Rank 0, after the runs: every input's row, the checks and the table's maths, the table written.
std::vector<ComparedScene> WriteTable(const std::vector<CompareInput>& inputs, const CompareOptions& options) {
  std::vector<ComparedScene> rows;
  for (const CompareInput& in : inputs) {
    const fs::path folder = in.run_folder.empty() ? options.base.output_dir / in.name : in.run_folder;
    if (!fs::is_regular_file(folder / "map.json"))
      throw std::runtime_error(in.name + ": its run gave no result (see above): nothing to compare");
    rows.push_back(ReadComparedRun(folder, in.name));
  }
  CheckOneLikelihood(rows);
  TabulateComparison(&rows, options.bars);
  fs::create_directories(options.base.output_dir);
  WriteAtomically(options.base.output_dir / "compare.json", ToJson(rows).dump(2) + "\n");
  WriteAtomically(options.base.output_dir / "compare.md", MarkdownTable(rows));
  return rows;
}

}  // namespace

std::vector<ComparedScene> CompareScenes(const CompareOptions& options, vk::Device& device) {
  const std::vector<CompareInput> inputs = ResolveInputs(options.inputs);
  const Ranks& ranks = options.base.ranks ? *options.base.ranks : Ranks::One();
  std::ostream* log = options.base.log;
  // compare's own settings first, so that --set can change them: the ladder, and no clutter
  // masks (each scene would mask what it fails to explain: other data for every scene).
  std::vector<SceneOverride> overrides = {{"sampler.evidence_rungs", std::to_string(options.rungs)},
                                          {"likelihood.clutter", "false"}};
  overrides.insert(overrides.end(), options.overrides.begin(), options.overrides.end());
  const CompareInput* finished = nullptr;
  std::vector<ListedScene> rest = LoadAndCheck(inputs, overrides, log, &finished);
  // A map.json left by an earlier compare into OUT must not stand in for a run that fails now.
  if (ranks.rank() == 0)
    for (const ListedScene& scene : rest) fs::remove(options.base.output_dir / scene.name / "map.json");

  // The common calibration: a finished run's, else the first scene's, run first as it would
  // run alone; the others then score with its σ, δ and κ.
  fs::path reference;
  std::string reference_rows;  // its summary.csv, header included
  if (finished) {
    reference = finished->run_folder;
  } else {
    if (log) *log << "vkrecon compare: " << rest.front().name << " first: its run calibrates the likelihood\n";
    ReconstructList({rest.front()}, overrides, options.base, ranks, device);
    if (ranks.rank() == 0) reference_rows = ReadWhole(options.base.output_dir / "summary.csv");
    reference = options.base.output_dir / rest.front().name;
    rest.erase(rest.begin());
  }
  const auto fixed = FixedLikelihood(ReadOnRoot(reference, ranks)["evidence"].value("likelihood", nlohmann::json()),
                                     reference / "map.json");
  overrides.insert(overrides.end(), fixed.begin(), fixed.end());
  if (!rest.empty()) {
    if (log) *log << "vkrecon compare: " << rest.size() << " scene(s) under that likelihood\n";
    ReconstructList(rest, overrides, options.base, ranks, device);
    if (ranks.rank() == 0) KeepReferenceRow(options.base.output_dir / "summary.csv", reference_rows);
  }
  if (ranks.rank() != 0) return {};
  return WriteTable(inputs, options);
}

}  // namespace vkr::recon
