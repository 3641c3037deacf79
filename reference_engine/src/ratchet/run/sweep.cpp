#include "ratchet/run/sweep.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "ratchet/io/atomic_file.hpp"
#include "ratchet/io/json_file.hpp"
#include "ratchet/io/state_file.hpp"
#include "ratchet/run/checkpoint.hpp"
#include "ratchet/run/packing.hpp"
#include "ratchet/run/run_output.hpp"
#include "ratchet/run/runner.hpp"
#include "ratchet/run/stop_request.hpp"
#include "ratchet/run/sweep_points.hpp"
#include "ratchet/scene/scene.hpp"

namespace ratchet {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(const std::string& source, const std::string& field, const std::string& expected) {
  throw SceneError(source + ": field '" + field + "': expected " + expected);
}

void set_path(json& j, const std::string& path, const json& value, const std::string& source) {
  apply_override(j, path + "=" + value.dump(), source);
}

}  // namespace

SweepPlan load_sweep(const std::string& path, const std::string& out_dir,
                     const std::vector<std::string>& overrides) {
  json j;
  try {
    j = read_json_file(path, "sweep file");
  } catch (const JsonFileError& e) {
    throw SceneError(e.what());
  }
  if (!j.is_object()) throw SceneError(path + ": not a JSON object (a sweep file is {\"scene\": ..., \"grid\" or \"points\": ...})");
  for (auto it = j.begin(); it != j.end(); ++it)
    if (it.key() != "scene" && it.key() != "grid" && it.key() != "points" && it.key() != "realizations" &&
        it.key() != "seeds" && it.key() != "set" && it.key() != "description")
      throw SceneError(path + ": field '" + it.key() +
                       "': unknown field (known fields here: scene, grid, points, realizations, seeds, set, "
                       "description)");
  SweepPlan plan;
  plan.source = path;
  plan.out_dir = out_dir;
  // Base scene: a path relative to the sweep file, or inline.
  if (!j.contains("scene")) fail(path, "scene", "a scene file path or an inline scene (the field is required)");
  json base;
  std::string scene_source = path;
  if (j.at("scene").is_string()) {
    const fs::path p = fs::path(path).parent_path() / j.at("scene").get<std::string>();
    try {
      base = read_json_file(p.string(), "scene file");
    } catch (const JsonFileError& e) {
      fail(path, "scene", std::string("a readable scene file in JSON (") + e.what() + ")");
    }
    scene_source = p.string();
  } else if (j.at("scene").is_object()) {
    base = j.at("scene");
  } else {
    fail(path, "scene", "a scene file path or an inline scene object");
  }
  if (j.contains("set")) {
    if (!j.at("set").is_object()) fail(path, "set", "an object {\"dotted.path\": value}");
    for (auto it = j.at("set").begin(); it != j.at("set").end(); ++it) set_path(base, it.key(), it.value(), path);
  }
  for (const std::string& assignment : overrides) apply_override(base, assignment, "--set " + assignment);
  // Seeds.
  std::vector<std::uint64_t> seeds;
  if (j.contains("seeds")) {
    if (!j.at("seeds").is_array() || j.at("seeds").empty()) fail(path, "seeds", "a non-empty list of integers >= 0");
    for (const json& s : j.at("seeds")) {
      if (!s.is_number_integer() || s.get<long long>() < 0) fail(path, "seeds", "a non-empty list of integers >= 0");
      seeds.push_back(s.get<std::uint64_t>());
    }
  } else {
    const json r = j.value("realizations", json(1));
    if (!r.is_number_integer() || r.get<int>() < 1) fail(path, "realizations", "an integer >= 1");
    for (int s = 1; s <= r.get<int>(); ++s) seeds.push_back(static_cast<std::uint64_t>(s));
  }
  // The points: the grid's cartesian product or the list, each one value per key.
  const std::vector<std::vector<json>> points = sweep_points(j, path, plan.grid_keys);
  int id = 0;
  for (const std::vector<json>& point : points) {
    for (std::uint64_t seed : seeds) {
      SweepRun run;
      run.id = id++;
      run.seed = seed;
      run.scene = base;
      for (std::size_t k = 0; k < point.size(); ++k) {
        run.params.emplace_back(plan.grid_keys[k], point[k]);
        set_path(run.scene, plan.grid_keys[k], point[k], path);
      }
      run.scene["seed"] = seed;
      // Check the run's scene now: a bad grid value stops the sweep before any work.
      try {
        const SceneDef scene = build_scene(run.scene, scene_source);
        // A packing pays when there is a settle stage and the run goes past it.
        if (has_settle_stage(scene) && (scene.settle.enabled || (scene.thermal.start_time > 0.0 &&
                                                                 scene.thermal.start_time + scene.dt <= scene.duration)))
          run.packing_key = packing_key(scene);
      } catch (const SceneError& e) {
        throw SceneError(std::string(e.what()) + " (in run " + std::to_string(run.id) + " of sweep " + path + ")");
      }
      plan.runs.push_back(std::move(run));
    }
  }
  // Packings in the order of their first run (a linear search: no unordered containers).
  for (const SweepRun& run : plan.runs) {
    if (run.packing_key.empty()) continue;
    auto it = std::find_if(plan.packings.begin(), plan.packings.end(),
                           [&](const SweepPacking& p) { return p.key == run.packing_key; });
    if (it == plan.packings.end()) plan.packings.push_back({run.packing_key, {run.id}});
    else it->runs.push_back(run.id);
  }
  return plan;
}

std::string run_dir(const SweepPlan& plan, int id) { return plan.out_dir + "/runs/" + std::to_string(id); }

namespace {

json read_run_json(const SweepPlan& plan, int id) {
  std::ifstream in(run_dir(plan, id) + "/run.json");
  if (!in) return json();
  const json j = json::parse(in, nullptr, false);
  return j.is_discarded() ? json() : j;
}

}  // namespace

std::optional<ResumePoint> resumable_checkpoint(const std::string& dir, const SceneDef& scene, std::string* why_not) {
  if (why_not != nullptr) why_not->clear();
  if (!std::filesystem::is_regular_file(dir + "/" + kCheckpointFileName)) return std::nullopt;
  std::string reason;
  try {
    ResumePoint point = read_checkpoint(dir);
    if (point.scene.hash == scene.hash) return point;
    reason = dir + "/" + kCheckpointFileName + ": a checkpoint of another scene (hash " + point.scene.hash +
             ", this run's is " + scene.hash + ")";
  } catch (const std::exception& e) {
    reason = e.what();
  }
  if (why_not != nullptr) *why_not = reason;
  return std::nullopt;
}

namespace {

// A run's run.json `j` shows it complete: completed, for the scene the sweep builds
// now, by this engine (an engine change reruns it: docs/sweeps.md, "Resume").
bool completed(const json& j, const SweepRun& run) {
  return j.is_object() && j.value("status", "") == "completed" &&
         j.value("scene_hash", "") == fnv1a_hex(run.scene.dump()) && other_engine(j.value("engine", json())).empty();
}

}  // namespace

bool run_completed(const SweepPlan& plan, const SweepRun& run) { return completed(read_run_json(plan, run.id), run); }

std::string packing_path(const SweepPlan& plan, const std::string& key) {
  return plan.out_dir + "/packings/" + key + ".state";
}

namespace {

// Empty when the packing file is there, whole and of this key; otherwise why not.
std::string packing_problem(const SweepPlan& plan, const SweepPacking& packing) {
  const std::string path = packing_path(plan, packing.key);
  std::error_code ec;
  if (!fs::exists(path, ec)) return "missing";
  try {
    const StateFile f = read_state_file(path);
    if (f.key != packing.key) return path + ": holds key " + f.key;
    // A packing of another engine may hold another bed: made again, never reused.
    if (const std::string other = other_engine(f.meta.value("engine", json())); !other.empty())
      return path + ": " + other;
    return "";
  } catch (const StateFileError& e) {
    return e.what();
  }
}

std::string id_list(const std::vector<int>& ids) {
  std::string s;
  for (int id : ids) s += (s.empty() ? "" : ", ") + std::to_string(id);
  return s;
}

}  // namespace

bool packing_ready(const SweepPlan& plan, const SweepPacking& packing) { return packing_problem(plan, packing).empty(); }

std::vector<int> needed_packings(const SweepPlan& plan) {
  std::vector<int> out;
  for (std::size_t i = 0; i < plan.packings.size(); ++i)
    for (int id : plan.packings[i].runs)
      if (!run_completed(plan, plan.runs[static_cast<std::size_t>(id)])) {
        out.push_back(static_cast<int>(i));
        break;
      }
  return out;
}

void make_packings(const SweepPlan& plan, const std::vector<int>& indices, int jobs,
                   const std::function<void(const std::string&)>& progress, int threads_per_run) {
  std::vector<int> todo;
  std::mutex mutex;
  for (int i : indices) {
    const std::string problem = packing_problem(plan, plan.packings[static_cast<std::size_t>(i)]);
    if (problem.empty()) continue;
    todo.push_back(i);
    if (problem != "missing" && progress) progress("packing unusable, making it again: " + problem);
  }
  if (progress)
    progress(std::to_string(indices.size() - todo.size()) + " of " + std::to_string(indices.size()) +
             " packings already made; making " + std::to_string(todo.size()));
  if (todo.empty()) return;
  // No throwing from here: under MPI the other ranks wait at a barrier. A folder that
  // cannot be made fails each packing's write instead (reported per packing).
  std::error_code ec;
  fs::create_directories(plan.out_dir + "/packings", ec);
  std::atomic<std::size_t> next{0};
  auto worker = [&]() {
#ifdef _OPENMP
    omp_set_num_threads(threads_per_run);
#endif
    for (std::size_t k = next++; k < todo.size() && stop_signal() == 0; k = next++) {
      const SweepPacking& p = plan.packings[static_cast<std::size_t>(todo[k])];
      const SweepRun& run = plan.runs[static_cast<std::size_t>(p.runs.front())];
      std::string line;
      try {
        const auto t0 = std::chrono::steady_clock::now();
        World world(build_scene(run.scene, plan.source + " run " + std::to_string(run.id)));
        // A pour keeps a checkpoint next to its packing and a stopped sweep goes on from it
        // (run/pour_checkpoint.hpp).
        const PourCheckpointing checkpoints = pour_checkpointing(packing_path(plan, p.key), world.scene());
        const json settle = settle_world(world, {}, checkpoints, [&](const std::string& note) {
          std::lock_guard<std::mutex> lock(mutex);
          if (progress) progress("packing " + p.key + ": " + note);
        });
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        write_packing(packing_path(plan, p.key), world, settle, {{"wall_seconds", seconds}});
        remove_pour_checkpoint(checkpoints);  // the packing is written: the pour is done
        std::ostringstream s;
        s << "packing " << p.key << " (seed " << run.seed << ", runs " << id_list(p.runs) << ") done in "
          << std::round(seconds) << " s, t = " << format_double(world.state().t);
        if (settle.at("ke_ratio").is_number()) s << ", KE/KE_peak = " << settle.at("ke_ratio").get<double>();
        line = s.str();
      } catch (const RunInterrupted& e) {
        line = "packing " + p.key + ": " + e.what();
      } catch (const std::exception& e) {
        line = "packing " + p.key + " FAILED: " + e.what();
      }
      std::lock_guard<std::mutex> lock(mutex);
      if (progress) progress(line);
    }
  };
  std::vector<std::thread> threads;
  for (int t = 0; t < std::max(1, std::min<int>(jobs, static_cast<int>(todo.size()))); ++t) threads.emplace_back(worker);
  for (std::thread& t : threads) t.join();
}

void run_sweep(const SweepPlan& plan, const std::vector<int>& ids, int jobs,
               const std::function<void(const std::string&)>& progress, int threads_per_run) {
  std::vector<int> todo;
  for (int id : ids)
    if (!run_completed(plan, plan.runs[static_cast<std::size_t>(id)])) todo.push_back(id);
  if (progress)
    progress(std::to_string(ids.size() - todo.size()) + " of " + std::to_string(ids.size()) +
             " runs already completed; running " + std::to_string(todo.size()));
  std::atomic<std::size_t> next{0};
  std::atomic<int> done{0};
  std::mutex mutex;
  std::string first_error;
  const auto start = std::chrono::steady_clock::now();
  auto worker = [&]() {
#ifdef _OPENMP
    omp_set_num_threads(threads_per_run);  // parallel over runs, and inside each as asked
#endif
    for (std::size_t k = next++; k < todo.size() && stop_signal() == 0; k = next++) {
      const SweepRun& run = plan.runs[static_cast<std::size_t>(todo[k])];
      std::string line;
      try {
        World world(build_scene(run.scene, plan.source + " run " + std::to_string(run.id)));
        RunOptions opt;
        opt.out_dir = run_dir(plan, run.id);
        opt.command_line = plan.command_line;
        std::string not_resumed;
        if (const std::optional<ResumePoint> point = resumable_checkpoint(opt.out_dir, world.scene(), &not_resumed)) {
          // An interrupted run goes on from its last checkpoint (run/checkpoint.hpp).
          resume_world(world, *point);
          opt.resume = point->run;
          if (progress) {
            std::lock_guard<std::mutex> lock(mutex);
            progress("run " + std::to_string(run.id) + " resumes at step " + std::to_string(world.state().step));
          }
        } else {
          if (!not_resumed.empty() && progress) {  // the steps it held are lost: say so
            std::lock_guard<std::mutex> lock(mutex);
            progress("run " + std::to_string(run.id) + " starts over, its checkpoint not resumed: " + not_resumed);
          }
          if (!run.packing_key.empty()) {
            const std::string path = packing_path(plan, run.packing_key);
            const json meta = load_packing(path, world);
            opt.packing = packing_reference(path, world);
            opt.packing_settle = meta.value("settle", json());
          }
        }
        const RunResult r = run_world(world, opt);
        const int n = ++done;
        const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const double left = el / n * static_cast<double>(todo.size() - static_cast<std::size_t>(n));
        std::ostringstream s;
        s << "run " << run.id << " done in " << std::round(r.wall_seconds) << " s (" << n << "/" << todo.size()
          << ", about " << std::round(left) << " s left)";
        line = s.str();
      } catch (const RunInterrupted& e) {
        line = "run " + std::to_string(run.id) + " stopped, checkpoint kept: " + e.what();
      } catch (const std::exception& e) {
        ++done;
        line = "run " + std::to_string(run.id) + " FAILED: " + e.what();
        std::lock_guard<std::mutex> lock(mutex);
        if (first_error.empty()) first_error = line;
      }
      std::lock_guard<std::mutex> lock(mutex);
      if (progress) progress(line);
    }
  };
  std::vector<std::thread> threads;
  for (int t = 0; t < std::max(1, jobs); ++t) threads.emplace_back(worker);
  for (std::thread& t : threads) t.join();
}

std::string summary_csv_cell(const json& v) {
  if (v.is_null()) return "";
  if (v.is_number_float()) return format_double(v.get<double>());
  if (v.is_number()) return v.dump();
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  const std::string text = v.is_string() ? v.get<std::string>() : v.dump();
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

void write_sweep_summary(const SweepPlan& plan) {
  // Columns: run, grid keys, thermal.alpha_p, seed, then the summary keys of the runs.
  std::vector<json> metas;
  std::vector<std::string> keys;
  for (const SweepRun& run : plan.runs) {
    metas.push_back(read_run_json(plan, run.id));
    const json& m = metas.back();
    if (m.is_object() && m.contains("summary") && m.at("summary").is_object())
      for (auto it = m.at("summary").begin(); it != m.at("summary").end(); ++it)
        if (it.value().is_number() || it.value().is_null())
          if (std::find(keys.begin(), keys.end(), it.key()) == keys.end()) keys.push_back(it.key());
  }
  std::sort(keys.begin(), keys.end());
  std::ostringstream csv, timings;
  csv << "run";
  for (const std::string& k : plan.grid_keys) csv << ',' << k;
  const bool has_alpha_p = std::find(plan.grid_keys.begin(), plan.grid_keys.end(), "thermal.alpha_p") != plan.grid_keys.end();
  if (!has_alpha_p) csv << ",thermal.alpha_p";
  csv << ",seed,packing";
  for (const std::string& k : keys) csv << ',' << k;
  csv << ",status\n";
  timings << "run,wall_seconds,steps\n";
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    const SweepRun& run = plan.runs[i];
    const json& m = metas[i];
    const bool ok = completed(m, run);
    csv << run.id;
    for (const auto& p : run.params) csv << ',' << summary_csv_cell(p.second);
    if (!has_alpha_p) {
      const SceneDef s = build_scene(run.scene, plan.source);
      csv << ',' << format_double(s.thermal.alpha_p);
    }
    csv << ',' << run.seed << ',';
    // The packing the run actually started from, as its run.json says.
    if (ok && m.contains("packing") && m.at("packing").is_object()) csv << m.at("packing").value("key", "");
    for (const std::string& k : keys)
      csv << ',' << (ok && m.at("summary").contains(k) ? summary_csv_cell(m.at("summary").at(k)) : "");
    csv << ',' << (ok ? "completed" : "missing") << '\n';
    timings << run.id << ',' << (ok ? format_double(m.value("wall_seconds", 0.0)) : "") << ','
            << (ok ? std::to_string(m.value("steps", 0)) : "") << '\n';
  }
  write_file_atomic(plan.out_dir + "/summary.csv", csv.str());
  write_file_atomic(plan.out_dir + "/timings.csv", timings.str());
}

}  // namespace ratchet
