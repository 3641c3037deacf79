// Settled packings (docs/sweeps.md, "Packings"): the bed poured and settled under
// gravity up to thermal.start_time, stored once and reused by every run whose scene
// differs only in what cannot act before start_time (the packing key). A run from a
// packing continues exactly as the run from t = 0 would have: State is all a restart
// needs (world/state.hpp).
#pragma once

#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "ratchet/world/world.hpp"

namespace ratchet {

// The scene JSON without the fields that cannot change the state before the thermal
// protocol starts (list in docs/sweeps.md): name, description, outputs, time.duration,
// solver.threads and the thermal fields other than T0 and start_time.
nlohmann::json packing_scene(const nlohmann::json& scene);

// FNV-1a 64 (16 hex digits) of packing_scene(scene.as_run), salted with the key version.
std::string packing_key(const SceneDef& scene);

// A scene has a settle stage (and so a packing) when it has a thermal section.
bool has_settle_stage(const SceneDef& scene);

// True while the next step still lies in the settle stage: it ends at the last state
// before the temperature leaves T0, i.e. the last step with t - start_time <= 0 in the
// same arithmetic as thermal/thermal_protocol.cpp. Nothing that the key leaves out
// can act up to that state.
bool next_step_settles(const World& world);

// The settle check: kinetic energy against its running peak, over the states of the
// settle stage (the initial state included).
class SettleMonitor {
 public:
  explicit SettleMonitor(const World& world);  // observes the current state
  void after_step(const World& world);         // no-op once the stage is over
  bool done() const { return done_; }
  // {t_end, step_end, ke_peak, ke_end, ke_ratio, ke_ratio_threshold, reached, t_settled}
  nlohmann::json record() const;

 private:
  void observe(const World& world);
  double threshold_ = 0.0;  // settle.ke_ratio; 0: none
  double peak_ = 0.0, ke_ = 0.0, t_ = 0.0, t_below_ = 0.0;
  std::int64_t step_ = 0;
  bool below_ = false, done_ = false;
};

// Steps `world` (fresh from its scene) to the end of the settle stage and returns the
// settle record. `each_step` is called after every step (progress).
nlohmann::json settle_world(World& world, const std::function<void(const World&)>& each_step = {});

// Writes the world's state as the scene's packing (atomic). `info` goes into the
// file's metadata next to the key, the packing scene and the settle record.
void write_packing(const std::string& path, const World& world, const nlohmann::json& settle,
                   const nlohmann::json& info = nlohmann::json::object());

// Replaces the state of `world` (fresh from its scene) by the packing in `path` after
// checking that it belongs to this scene. Throws StateFileError (io/state_file.hpp)
// naming the file and what did not match. Returns the packing's metadata.
nlohmann::json load_packing(const std::string& path, World& world);

// "<file>: packing <key>" style description for run.json: {file, key, step, t}.
nlohmann::json packing_reference(const std::string& path, const World& world);

}  // namespace ratchet
