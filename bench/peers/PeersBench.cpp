// The peers benchmark (PeersBench.h): `run` and NLopt's methods on the same synthesised
// photographs, each watched through hooks (Reconstruct's RunObserver, FitMap's callback).

#include "bench/peers/PeersBench.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>

#include "engine/common/InputError.h"
#include "pipelines/rendering/ViewRendering.h"
#include "recon/AtomicWrite.h"
#include "recon/Fit.h"
#include "recon/Reconstruct.h"
#include "recon/SearchSetup.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace vkr {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// An asset's truth and its parameters' prior widths (as scripts/noise_study.py's: hi − lo,
// or 4 sd), which make errors comparable across parameters.
struct Truth {
  std::vector<double> values, widths;
  // |ψ − truth| / width per parameter.
  std::vector<double> Errors(const std::vector<double>& psi) const {
    std::vector<double> e;
    for (size_t i = 0; i < values.size(); ++i) e.push_back(std::abs(psi[i] - values[i]) / widths[i]);
    return e;
  }
};

double Median(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return std::isnan(x); }), v.end());
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Counts what a search spends and notes when its running MAP first comes within tolerance.
class Watch {
 public:
  Watch(const Truth& truth, double tolerance, PeersRow* row)
      : truth_(truth), tolerance_(tolerance), row_(*row), start_(Clock::now()) {
    row_.evaluations_to = row_.equivalents_to = row_.seconds_to = kNaN;
  }
  void Spent(int level, size_t hypotheses) {
    row_.evaluations += double(hypotheses);
    row_.equivalents += double(hypotheses) * std::pow(4.0, -level);
    row_.seconds = Seconds();  // the last evaluation ends the search (run's outputs come after)
  }
  void Best(const std::vector<double>& psi) {
    if (row_.reached) return;
    const std::vector<double> e = truth_.Errors(psi);
    if (*std::max_element(e.begin(), e.end()) > tolerance_) return;
    row_.reached = true;
    row_.evaluations_to = row_.evaluations;
    row_.equivalents_to = row_.equivalents;
    row_.seconds_to = Seconds();
  }
  void Final(const std::vector<double>& map) {
    const std::vector<double> e = truth_.Errors(map);
    row_.median_error = Median(e);
    row_.max_error = *std::max_element(e.begin(), e.end());
  }

 private:
  double Seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  const Truth& truth_;
  double tolerance_;
  PeersRow& row_;
  Clock::time_point start_;
};

struct Asset {
  std::string name;
  fs::path scene, synth_scene, truth_file;
};

Asset FindAsset(const fs::path& assets_dir, const std::string& name) {
  Asset a{name, assets_dir / name / "scene.json", assets_dir / name / "synth.json", assets_dir / name / "truth.json"};
  for (const fs::path& p : {a.scene, a.truth_file})
    if (!fs::is_regular_file(p)) throw InputError(p.string(), "", "no such file: unknown asset '" + name + "'");
  // The clutter assets photograph a truer scene than the model (assets/make_assets.py).
  if (!fs::is_regular_file(a.synth_scene)) a.synth_scene = a.scene;
  return a;
}

std::string Number(double x, int precision) {
  if (std::isnan(x)) return "—";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", precision, x);
  return buf;
}

// The fields of PeersJson that say what a row measured: a row kept by --resume was
// measured with these. The seeds and assets may change: rows outside them are dropped.
nlohmann::json SettingsJson(const PeersOptions& o) {
  std::vector<std::string> methods = {"run"};
  for (opt::SearchMethod m : o.methods) methods.push_back(opt::ToString(m));
  nlohmann::json overrides = nlohmann::json::array();
  for (const SceneOverride& set : o.overrides) overrides.push_back(set.path + "=" + set.value);
  return {{"sigma", o.sigma}, {"overrides", overrides}, {"scale", o.scale},   {"budget", o.budget},
          {"tolerance", o.tolerance}, {"methods", methods}, {"quick", o.quick}};
}

double NumberOrNaN(const nlohmann::json& j) { return j.is_null() ? kNaN : j.get<double>(); }

PeersRow RowFromJson(const nlohmann::json& j) {
  PeersRow r{j.at("asset").get<std::string>(), j.at("method").get<std::string>(), j.at("seed").get<int>()};
  r.reached = j.at("reached").get<bool>();
  r.evaluations_to = NumberOrNaN(j.at("evaluations_to"));
  r.equivalents_to = NumberOrNaN(j.at("equivalents_to"));
  r.seconds_to = NumberOrNaN(j.at("seconds_to"));
  r.evaluations = j.at("evaluations").get<double>();
  r.equivalents = j.at("equivalents").get<double>();
  r.seconds = j.at("seconds").get<double>();
  r.median_error = j.at("median_error").get<double>();
  r.max_error = j.at("max_error").get<double>();
  return r;
}

// What --resume keeps of work_dir/peers.json: its device and, per (asset, seed) with a row
// for every method, those rows. Empty without --resume or before the first group ended.
struct KeptRows {
  fs::path file;
  std::string device;
  double wall_s = 0.0;
  std::map<std::pair<std::string, int>, std::vector<PeersRow>> groups;
};

KeptRows ReadKeptRows(const PeersOptions& options) {
  KeptRows kept;
  if (!options.resume) return kept;
  if (options.work_dir.empty())
    throw InputError("", "--resume", "needs --work: the folder whose peers.json the bench goes on from");
  kept.file = fs::absolute(options.work_dir) / "peers.json";
  if (!fs::exists(kept.file)) return kept;  // cut short before the first group ended
  std::ifstream in(kept.file, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    throw InputError(kept.file.string(), "", std::string("cannot resume: not JSON: ") + e.what());
  }
  if (!j.is_object()) throw InputError(kept.file.string(), "", "cannot resume: not a JSON object");
  const nlohmann::json settings = SettingsJson(options);  // outlives items(): the loop holds no temporary
  for (const auto& [key, value] : settings.items())
    if (!j.contains(key) || j[key] != value)
      throw InputError(kept.file.string(), key,
                       "measured with other settings (" + (j.contains(key) ? j[key].dump() : "none") + ", now " +
                           value.dump() + "): resume with the same options, or use another --work folder");
  std::map<std::pair<std::string, int>, std::vector<PeersRow>> groups;
  std::string field;  // for the message, should a field have the wrong type
  try {
    field = "rows";
    const nlohmann::json rows = j.value("rows", nlohmann::json::array());
    for (size_t i = 0; i < rows.size(); ++i) {
      field = "rows[" + std::to_string(i) + "]";
      const PeersRow row = RowFromJson(rows.at(i));
      groups[{row.asset, row.seed}].push_back(row);
    }
    field = "device";
    kept.device = j.value("device", "");
    field = "wall_s";
    kept.wall_s = j.value("wall_s", 0.0);
  } catch (const std::exception& e) {
    throw InputError(kept.file.string(), field, std::string("cannot resume: ") + e.what());
  }
  // A group is kept only whole: one row per method, in the bench's order.
  const std::vector<std::string> methods = settings["methods"].get<std::vector<std::string>>();
  for (auto& [key, group] : groups) {
    std::vector<std::string> in_group;
    for (const PeersRow& row : group) in_group.push_back(row.method);
    if (in_group == methods) kept.groups[key] = std::move(group);
  }
  return kept;
}

std::string GroupLine(const std::string& asset, int seed, std::vector<PeersRow>::const_iterator begin,
                      std::vector<PeersRow>::const_iterator end) {
  std::ostringstream line;
  line << asset << " seed " << seed << ":";
  for (auto it = begin; it != end; ++it)
    line << "  " << it->method << (it->reached ? " ✓" : " ✗") << " " << Number(it->equivalents_to, 0) << " eq, "
         << Number(100 * it->median_error, 3) << " %";
  return line.str();
}

}  // namespace

PeersOptions PeersOptions::Quick() {
  PeersOptions o;
  o.quick = true;
  o.assets = {"box", "poster"};
  o.seeds = {1};
  o.scale = 0.25;
  o.budget = 60.0;
  // A 128² atlas for every method (the same likelihood); a short run.
  o.overrides = {{"sampler.iterations", "60"}, {"likelihood.atlas", "128"}};
  return o;
}

void CheckPeersOptions(const PeersOptions& options) {
  for (const std::string& name : options.assets) FindAsset(options.assets_dir, name);
  ReadKeptRows(options);
}

PeersReport RunPeers(const PeersOptions& options, vk::Device& device, const PeersProgress& progress) {
  std::vector<Asset> assets;
  for (const std::string& name : options.assets) assets.push_back(FindAsset(options.assets_dir, name));
  const bool temporary = options.work_dir.empty();
  const fs::path work = temporary ? fs::temp_directory_path() / ("vkrecon-peers-" + std::to_string(getpid()))
                                  : fs::absolute(options.work_dir);
  PeersReport report;
  report.device = device.name();
  report.options = options;
  KeptRows kept = ReadKeptRows(options);
  // Timings from another device would not compare.
  if (!kept.groups.empty() && kept.device != report.device)
    throw InputError(kept.file.string(), "device", "measured on " + kept.device + ", now " + report.device +
                                                       ": resume on the same device, or use another --work folder");
  if (progress) progress("on " + report.device);
  const auto start = Clock::now();
  // Seed-major: the rows kept so far cover every asset, should a long run be cut short.
  for (const int seed : options.seeds)
    for (const Asset& asset : assets) {
      if (auto it = kept.groups.find({asset.name, seed}); it != kept.groups.end()) {
        report.rows.insert(report.rows.end(), it->second.begin(), it->second.end());
        if (progress) progress(GroupLine(asset.name, seed, it->second.begin(), it->second.end()) + "  (kept)");
        continue;
      }
      const fs::path folder = work / asset.name / ("seed" + std::to_string(seed));
      // The reference photographs, as scripts/noise_study.py makes them.
      SynthOptions synth;
      synth.scene_file = asset.synth_scene;
      synth.at_file = asset.truth_file;
      synth.output_dir = folder / "images";
      synth.noise_sigma = options.sigma;
      synth.seed = uint64_t(seed);
      synth.scale = options.scale;
      SynthesiseImages(synth, device);
      std::vector<SceneOverride> sets = {{"images", synth.output_dir.string()},
                                         {"cameras", (synth.output_dir / "cameras.json").string()},
                                         {"likelihood.sigma", "auto"},
                                         {"sampler.seed", std::to_string(seed)}};
      sets.insert(sets.end(), options.overrides.begin(), options.overrides.end());
      const Scene scene = recon::LoadSearchScene(asset.scene, sets);
      Truth truth;
      truth.values = scene.ValuesFromFile(asset.truth_file);
      for (const opt::ParameterSpec& p : recon::ParameterSpecs(scene)) truth.widths.push_back(p.Width());

      {  // vkrecon run, its running MAP watched frame by frame
        PeersRow row{asset.name, "run", seed};
        Watch watch(truth, options.tolerance, &row);
        recon::ReconstructOptions run;
        run.scene = std::make_shared<const Scene>(recon::LoadSearchScene(asset.scene, sets));
        run.output_dir = folder / "run";
        run.quiet = true;
        run.observer.evaluated = [&](int level, size_t n) { watch.Spent(level, n); };
        run.observer.best = [&](const std::vector<double>& psi) { watch.Best(psi); };
        recon::ReconstructSummary result;
        recon::Reconstruct(run, device, &result);
        watch.Final(result.map());
        report.rows.push_back(row);
      }
      for (const opt::SearchMethod method : options.methods) {
        PeersRow row{asset.name, opt::ToString(method), seed};
        Watch watch(truth, options.tolerance, &row);
        recon::FitOptions fit;
        fit.scene_file = asset.scene;
        fit.overrides = sets;
        fit.method = method;
        fit.evaluations = options.budget;
        fit.restarts = 0;  // the method as NLopt runs it: what a user would otherwise pick
        fit.quiet = true;
        // The running MAP as the sampler keeps it: the best at the current level.
        int level = -1;
        double best = -INFINITY;
        fit.on_evaluation = [&](const opt::SearchEvaluation& e) {
          watch.Spent(e.level, 1);
          if (e.level != level) best = -INFINITY;
          level = e.level;
          if (!(e.log_posterior > best)) return;
          best = e.log_posterior;
          watch.Best(*e.psi);
        };
        const recon::FitResult result = recon::FitMap(fit, device);
        watch.Final(result.summary.map);
        report.rows.push_back(row);
      }
      // The rows so far, kept beside the work: an interrupted 45-minute run still leaves them.
      if (!temporary) {
        report.wall_s = kept.wall_s + std::chrono::duration<double>(Clock::now() - start).count();
        recon::WriteAtomically(work / "peers.json", PeersJson(report).dump(2) + "\n");
      }
      if (progress)
        progress(GroupLine(asset.name, seed, report.rows.end() - std::ptrdiff_t(1 + options.methods.size()),
                           report.rows.end()));
    }
  // With --resume, the wall time of the sessions together.
  report.wall_s = kept.wall_s + std::chrono::duration<double>(Clock::now() - start).count();
  if (temporary) fs::remove_all(work);
  return report;
}

nlohmann::json PeersJson(const PeersReport& report) {
  auto number = [](double x) { return std::isnan(x) ? nlohmann::json(nullptr) : nlohmann::json(x); };
  nlohmann::json rows = nlohmann::json::array();
  for (const PeersRow& r : report.rows)
    rows.push_back({{"asset", r.asset}, {"seed", r.seed}, {"method", r.method}, {"reached", r.reached},
                    {"evaluations_to", number(r.evaluations_to)}, {"equivalents_to", number(r.equivalents_to)},
                    {"seconds_to", number(r.seconds_to)}, {"evaluations", r.evaluations},
                    {"equivalents", r.equivalents}, {"seconds", r.seconds}, {"median_error", r.median_error},
                    {"max_error", r.max_error}});
  const PeersOptions& o = report.options;
  nlohmann::json j = SettingsJson(o);
  j.update({{"device", report.device}, {"seeds", o.seeds}, {"assets", o.assets}, {"wall_s", report.wall_s},
            {"rows", rows}});
  return j;
}

std::string PeersTable(const PeersReport& report) {
  std::ostringstream out;
  out << "| asset | method | reached 1 % | evaluations to 1 % | full-res eq. to 1 % | s to 1 % | evaluations | "
         "full-res eq. | s | final median error % | final max error % |\n"
      << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::vector<std::string> methods = {"run"};
  for (opt::SearchMethod m : report.options.methods) methods.push_back(opt::ToString(m));
  for (const std::string& asset : report.options.assets)
    for (const std::string& method : methods) {
      std::map<std::string, std::vector<double>> c;
      int reached = 0, n = 0;
      for (const PeersRow& r : report.rows) {
        if (r.asset != asset || r.method != method) continue;
        ++n;
        reached += r.reached;
        c["et"].push_back(r.evaluations_to);
        c["qt"].push_back(r.equivalents_to);
        c["st"].push_back(r.seconds_to);
        c["e"].push_back(r.evaluations);
        c["q"].push_back(r.equivalents);
        c["s"].push_back(r.seconds);
        c["me"].push_back(100 * r.median_error);
        c["xe"].push_back(100 * r.max_error);
      }
      if (n == 0) continue;
      out << "| " << asset << " | " << method << " | " << reached << "/" << n << " | " << Number(Median(c["et"]), 0)
          << " | " << Number(Median(c["qt"]), 0) << " | " << Number(Median(c["st"]), 1) << " | "
          << Number(Median(c["e"]), 0) << " | " << Number(Median(c["q"]), 0) << " | " << Number(Median(c["s"]), 1)
          << " | " << Number(Median(c["me"]), 3) << " | " << Number(Median(c["xe"]), 3) << " |\n";
    }
  out << "\nMedians over the seeds (the \"to 1 %\" columns over the seeds that got there).\n";
  return out.str();
}

}  // namespace vkr
