// Settled packings (docs/sweeps.md, "Packings"): the bed poured and settled under
// gravity, stored once and reused by every run whose scene differs only in what cannot
// act before the settle stage ends (the packing key). The settle stage ends
// - with a settle section: at the first state whose kinetic energy is at most
//   settle.ke_ratio x its peak (the run fails if none comes by settle.max_time);
// - without: at thermal.start_time.
// A run from a packing continues exactly as the run from t = 0 would have: State is
// all a restart needs (world/state.hpp).
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "ratchet/run/pour_checkpoint.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

// The scene JSON without the fields that cannot change the state before the settle
// stage ends (list in docs/sweeps.md): name, description, outputs, time.duration,
// solver.threads and the thermal fields other than T0 (and start_time, with a settle
// section: it then counts from the end of the stage).
nlohmann::json packing_scene(const nlohmann::json& scene);

// FNV-1a 64 (16 hex digits) of packing_scene(scene.as_run), salted with the key version.
std::string packing_key(const SceneDef& scene);

// A scene has a settle stage (and so a packing) when it has a thermal section.
bool has_settle_stage(const SceneDef& scene);

// Thrown when a settle section's threshold is not reached by settle.max_time.
struct SettleError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Watches the settle stage: kinetic energy against its running peak, over the states
// of the stage (the initial state included), and ends the stage.
class SettleMonitor {
 public:
  explicit SettleMonitor(World& world);  // observes the current state
  // A resumed run (run/checkpoint.hpp): the monitor as save() left it, observing nothing.
  SettleMonitor(const World& world, const nlohmann::json& saved);
  nlohmann::json save() const;
  // Observes the state after a step; with a settle section, ends the world's settle
  // stage at the first state at or below the threshold (World::end_settle_stage), or
  // throws SettleError at settle.max_time. A no-op once the stage is over.
  void after_step(World& world);
  bool done() const { return done_; }
  // {t_end, step_end, ke_peak, ke_end, ke_ratio, ke_ratio_threshold, reached, t_settled}
  nlohmann::json record() const;

 private:
  void observe(const World& world);
  void check(World& world);
  double threshold_ = 0.0;  // settle.ke_ratio; 0: no settle section
  double peak_ = 0.0, ke_ = 0.0, t_ = 0.0;
  std::int64_t step_ = 0;
  bool below_ = false, done_ = false;
};

// Steps `world` (fresh from its scene) to the end of the settle stage and returns the
// settle record. `each_step` is called after every step (progress). With a checkpoint
// path (run/pour_checkpoint.hpp) the pour first goes on from the checkpoint there, if it
// is this pour's, writes one every `checkpoints.every` steps, and on a stop request
// (run/stop_request.hpp) writes one and throws RunInterrupted; `note` hears which
// checkpoint was resumed or why one was not used. The caller removes the checkpoint once
// the packing is written.
nlohmann::json settle_world(World& world, const std::function<void(const World&)>& each_step = {},
                            const PourCheckpointing& checkpoints = {},
                            const std::function<void(const std::string&)>& note = {});

// Writes the world's state as the scene's packing (atomic). `info` goes into the
// file's metadata next to the key, the packing scene and the settle record.
void write_packing(const std::string& path, const World& world, const nlohmann::json& settle,
                   const nlohmann::json& info = nlohmann::json::object());

// Replaces the state of `world` (fresh from its scene) by the packing in `path` after
// checking that it belongs to this scene, and ends the world's settle stage there.
// Throws StateFileError (io/state_file.hpp) naming the file and what did not match.
// Returns the packing's metadata.
nlohmann::json load_packing(const std::string& path, World& world);

// "<file>: packing <key>" style description for run.json: {file, key, step, t}.
nlohmann::json packing_reference(const std::string& path, const World& world);

}  // namespace ratchet
