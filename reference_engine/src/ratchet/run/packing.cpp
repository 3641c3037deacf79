#include "ratchet/run/packing.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "ratchet/io/json_numbers.hpp"
#include "ratchet/io/state_file.hpp"
#include "ratchet/observe/energy.hpp"
#include "ratchet/run/run_output.hpp"
#include "ratchet/run/runner.hpp"
#include "ratchet/run/state_bounds.hpp"
#include "ratchet/run/stop_request.hpp"
#include "ratchet/run/time_marks.hpp"

namespace ratchet {

using nlohmann::json;

namespace {

// Bumped whenever the rule of packing_scene changes, so old packings stop matching.
constexpr const char* kKeySalt = "ratchet packing key 2\n";  // 2: settle sections end by KE

// A number for a message: 6 significant digits.
std::string shown(double x) {
  std::ostringstream o;
  o << x;
  return o.str();
}

std::string shown(const json& j) {
  std::string s = j.dump();
  return s.size() > 40 ? s.substr(0, 37) + "..." : s;
}

// The first few fields in which two scenes differ, as "field 'a.b' is X in the
// packing's scene and Y in this one".
void differences(const json& a, const json& b, const std::string& path, std::vector<std::string>& out) {
  if (out.size() >= 3 || a == b) return;
  if (a.is_object() && b.is_object()) {
    std::vector<std::string> keys;
    for (auto it = a.begin(); it != a.end(); ++it) keys.push_back(it.key());
    for (auto it = b.begin(); it != b.end(); ++it) keys.push_back(it.key());
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    for (const std::string& k : keys) {
      const std::string p = path.empty() ? k : path + "." + k;
      if (!a.contains(k)) out.push_back("field '" + p + "' is absent in the packing's scene and " + shown(b.at(k)) + " in this one");
      else if (!b.contains(k)) out.push_back("field '" + p + "' is " + shown(a.at(k)) + " in the packing's scene and absent in this one");
      else differences(a.at(k), b.at(k), p, out);
      if (out.size() >= 3) return;
    }
    return;
  }
  out.push_back("field '" + (path.empty() ? std::string("(top level)") : path) + "' is " + shown(a) +
                " in the packing's scene and " + shown(b) + " in this one");
}

// How closely the solve converges, the contact compliance, the gap relaxation and the
// manifold reuse: a packing fixes the bed, and a run from it may vary these, so that
// settings are compared on the same bed (the study of what accuracy costs; docs/cli.md).
// A compliance moves a rested bed's overlaps by less than the contact margin
// (docs/method.md s. 5); p_gap only sets how fast the overlaps left are closed; manifold
// reuse moves a gap by less than its bound (contact/manifold_reuse.hpp); the tangential
// law only says how a loaded compliant contact moves.
constexpr const char* kSolveKnobs[] = {"method",         "tolerance",  "criterion",      "max_iterations",
                                      "acceleration",   "compliance", "tangential_law", "anderson_depth",
                                      "p_gap",          "manifold_reuse", "stall_fallback", "slide_newton_steps"};

json without_solve_knobs(json scene) {
  if (scene.is_object() && scene.contains("solver") && scene["solver"].is_object())
    for (const char* k : kSolveKnobs) scene["solver"].erase(k);
  // The time step too, when a settle section ends the stage: the run then counts its
  // steps from the packing's state at its own h (World::end_settle_stage). Without one
  // the packing's step number is in the packing's h.
  if (scene.is_object() && scene.contains("settle") && scene.contains("time") && scene["time"].is_object())
    scene["time"].erase("dt");
  return scene;
}

}  // namespace

json packing_scene(const json& scene) {
  json j = scene;
  if (!j.is_object()) return j;
  for (const char* k : {"name", "description", "outputs"}) j.erase(k);
  if (!j.contains("seed")) j["seed"] = 1;  // the default, written out: a sweep always writes it
  if (j.contains("time") && j["time"].is_object()) j["time"].erase("duration");
  if (j.contains("solver") && j["solver"].is_object()) j["solver"].erase("threads");  // results do not depend on it
  // T stays T0 (so s_p = s_c = 1) until the settle stage ends: the shape of the cycle
  // and the expansion coefficients cannot act before then; with a settle section
  // neither can start_time, which counts from the end of the stage.
  if (j.contains("thermal") && j["thermal"].is_object()) {
    for (const char* k : {"T1", "heat_time", "hold_time", "cool_time", "cycles", "alpha_p", "alpha_c"}) j["thermal"].erase(k);
    if (j.contains("settle")) j["thermal"].erase("start_time");
  }
  // Nor can whether the floor's material expands: it moves with s_c, which stays 1.
  if (j.contains("container") && j["container"].is_object()) j["container"].erase("floor_expands");
  return j;
}

std::string packing_key(const SceneDef& scene) { return fnv1a_hex(kKeySalt + packing_scene(scene.as_run).dump()); }

bool has_settle_stage(const SceneDef& scene) { return scene.thermal.enabled; }

namespace {
// Without a settle section the stage ends at the last state before the temperature
// leaves T0: the last step with t - start_time <= 0, in the same arithmetic as
// temperature() (thermal/thermal_protocol.cpp): t_abs = t + h, then t_abs - start_time.
bool settles_after(const SceneDef& s, double t) {
  return has_settle_stage(s) && (t + s.dt) - s.thermal.start_time <= 0.0;
}
}  // namespace

SettleMonitor::SettleMonitor(World& world)
    : threshold_(world.scene().settle.enabled ? world.scene().settle.ke_ratio : 0.0) {
  done_ = !has_settle_stage(world.scene()) || (world.scene().settle.enabled && !world.settling());
  if (done_) return;
  observe(world);
  check(world);
}

SettleMonitor::SettleMonitor(const World& world, const nlohmann::json& saved)
    : threshold_(world.scene().settle.enabled ? world.scene().settle.ke_ratio : 0.0),
      peak_(number_from_json(saved.at("peak"))),
      ke_(number_from_json(saved.at("ke"))),
      t_(number_from_json(saved.at("t"))),
      step_(saved.at("step").get<std::int64_t>()),
      below_(saved.at("below").get<bool>()),
      done_(saved.at("done").get<bool>()) {}

nlohmann::json SettleMonitor::save() const {
  return {{"peak", json_number(peak_)}, {"ke", json_number(ke_)}, {"t", json_number(t_)},
          {"step", step_},             {"below", below_},         {"done", done_}};
}

void SettleMonitor::after_step(World& world) {
  if (done_) return;
  observe(world);
  check(world);
}

void SettleMonitor::observe(const World& world) {
  ke_ = kinetic_energy(world.scene(), world.state());
  peak_ = std::max(peak_, ke_);
  t_ = world.state().t;
  step_ = world.state().step;
}

void SettleMonitor::check(World& world) {
  const SceneDef& s = world.scene();
  if (!s.settle.enabled) {
    done_ = !settles_after(s, t_);
    return;
  }
  // The initial state does not count: a bed released at rest has KE = peak = 0.
  below_ = step_ > 0 && ke_ <= threshold_ * peak_;
  if (below_) {
    world.end_settle_stage();
    done_ = true;
    return;
  }
  if (t_ >= s.settle.max_time - kTimeRoundTol * s.dt)
    throw SettleError(s.source + ": the bed did not settle by settle.max_time = " + shown(s.settle.max_time) +
                      ": KE/KE_peak = " + shown(peak_ > 0.0 ? ke_ / peak_ : 0.0) + " at t = " + shown(t_) +
                      " is above settle.ke_ratio = " + shown(threshold_) + "; raise settle.max_time or settle.ke_ratio");
}

json SettleMonitor::record() const {
  const bool check = threshold_ > 0.0;
  return json{{"t_end", t_},
              {"step_end", step_},
              {"ke_peak", peak_},
              {"ke_end", ke_},
              {"ke_ratio", peak_ > 0.0 ? json(ke_ / peak_) : json(nullptr)},
              {"ke_ratio_threshold", check ? json(threshold_) : json(nullptr)},
              {"reached", check ? json(below_) : json(nullptr)},
              {"t_settled", check && below_ ? json(t_) : json(nullptr)}};
}

namespace {

// The settle stage's steps from where the world and the monitor are, with the pour's
// checkpoints (settle_world).
void pour(World& world, SettleMonitor& monitor, const std::function<void(const World&)>& each_step,
          const PourCheckpointing& checkpoints) {
  const SceneDef& s = world.scene();
  while (!monitor.done()) {
    if (!checkpoints.path.empty()) {
      if (const int sig = stop_signal(); sig != 0) {
        write_pour_checkpoint(checkpoints.path, world, monitor.save());
        throw RunInterrupted(s.source + ": the pour stopped by " + signal_name(sig) + " at step " +
                                 std::to_string(world.state().step) + ", its checkpoint in " + checkpoints.path,
                             sig);
      }
    }
    world.step();
    if (!std::isfinite(kinetic_energy(world.scene(), world.state())))
      throw RunError(s.source + ": the state became non-finite at step " + std::to_string(world.state().step) +
                     " (t = " + std::to_string(world.state().t) + ") while settling; the time step may be too large");
    if (const std::string wrong = unphysical_state(world); !wrong.empty())
      throw RunError(s.source + ": the state became unphysical at step " + std::to_string(world.state().step) +
                     " (t = " + std::to_string(world.state().t) + ") while settling: " + wrong +
                     "; the time step may be too large for the speeds of the pour");
    monitor.after_step(world);
    if (each_step) each_step(world);
    if (!checkpoints.path.empty() && checkpoints.every > 0 && !monitor.done() &&
        world.state().step % checkpoints.every == 0)
      write_pour_checkpoint(checkpoints.path, world, monitor.save());
  }
}

}  // namespace

json settle_world(World& world, const std::function<void(const World&)>& each_step,
                  const PourCheckpointing& checkpoints, const std::function<void(const std::string&)>& note) {
  const SceneDef& s = world.scene();
  if (!has_settle_stage(s))
    throw std::invalid_argument(s.source + ": field 'thermal': expected a thermal section (a packing is the bed at "
                                           "the end of the settle stage)");
  std::optional<SettleMonitor> resumed;
  if (!checkpoints.path.empty()) {
    std::string why_not;
    const json saved = resume_pour(checkpoints.path, world, &why_not);
    if (!saved.is_null()) {
      resumed.emplace(world, saved);
      if (note) note("resumes the pour from " + checkpoints.path + " at step " + std::to_string(world.state().step));
    } else if (!why_not.empty() && note) {
      note("not resuming the pour: " + why_not + "; pouring from the start");
    }
  }
  SettleMonitor monitor = resumed ? *resumed : SettleMonitor(world);
  try {
    pour(world, monitor, each_step, checkpoints);
  } catch (const RunInterrupted&) {
    throw;
  } catch (...) {
    remove_pour_checkpoint(checkpoints);  // a failed pour fails again from it: nothing to go on from
    throw;
  }
  return monitor.record();
}

void write_packing(const std::string& path, const World& world, const json& settle, const json& info) {
  const SceneDef& s = world.scene();
  StateFile f;
  f.key = packing_key(s);
  f.meta = info.is_object() ? info : json::object();
  f.meta["key"] = f.key;
  f.meta["bodies"] = s.bodies.size();
  f.meta["packing_scene"] = packing_scene(s.as_run);
  f.meta["settle"] = settle;
  f.meta["made_from"] = {{"scene_file", s.source}, {"scene_hash", s.hash}};
  f.meta["engine"] = engine_record();
  f.state = world.state();
  write_state_file(path, f);
}

json load_packing(const std::string& path, World& world) {
  const SceneDef& s = world.scene();
  if (!has_settle_stage(s))
    throw StateFileError(path + ": cannot start " + s.source +
                         " from a packing: field 'thermal': expected a thermal section (a packing is the bed at "
                         "thermal.start_time)");
  StateFile f = read_state_file(path);
  const std::string key = packing_key(s);
  if (f.state.x.size() != s.bodies.size())
    throw StateFileError(path + ": packing of " + std::to_string(f.state.x.size()) + " bodies, but " + s.source + " has " +
                         std::to_string(s.bodies.size()));
  // A key differs also when only the solve knobs differ; such a packing is the same bed.
  const bool same_bed = f.meta.contains("packing_scene") &&
                        without_solve_knobs(f.meta.at("packing_scene")) == without_solve_knobs(packing_scene(s.as_run));
  if (f.key != key && !same_bed) {
    std::vector<std::string> diff;
    if (f.meta.contains("packing_scene")) differences(f.meta.at("packing_scene"), packing_scene(s.as_run), "", diff);
    std::string what;
    for (const std::string& d : diff) what += "; " + d;
    throw StateFileError(path + ": packing of a different scene: its key is " + f.key + ", the packing key of " + s.source +
                         " is " + key + what);
  }
  if (s.settle.enabled) {
    const json settle = f.meta.value("settle", json());
    if (!settle.is_object() || settle.value("reached", json()) != true)
      throw StateFileError(path + ": the packing's settle record does not say that the bed reached settle.ke_ratio");
    if (f.state.t > s.settle.max_time + kTimeRoundTol * s.dt)
      throw StateFileError(path + ": the packing ends at t = " + shown(f.state.t) + ", after settle.max_time = " +
                           shown(s.settle.max_time) + " of " + s.source);
  } else {
    if (f.state.step > s.steps)
      throw StateFileError(path + ": the packing ends at step " + std::to_string(f.state.step) + ", after the last step (" +
                           std::to_string(s.steps) + ") of " + s.source + " (field 'time.duration')");
    if (settles_after(s, f.state.t) || f.state.t - s.thermal.start_time > 0.0)
      throw StateFileError(path + ": the packing (t = " + std::to_string(f.state.t) +
                           ") does not end where the settle stage of " + s.source +
                           " ends (thermal.start_time = " + std::to_string(s.thermal.start_time) + ")");
  }
  world.mutable_state() = std::move(f.state);
  if (s.settle.enabled) world.end_settle_stage();
  return f.meta;
}

json packing_reference(const std::string& path, const World& world) {
  return json{{"file", path}, {"key", packing_key(world.scene())}, {"step", world.state().step}, {"t", world.state().t}};
}

}  // namespace ratchet
