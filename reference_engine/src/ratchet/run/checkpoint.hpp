// Checkpoints and resuming (docs/output-format.md, "Checkpoints"): DIR/checkpoint.state
// is a state file (io/state_file.hpp) whose metadata holds, besides the State, all a run
// needs to go on exactly as if it had never stopped: the scene as run, the world's
// progress (world/world.hpp, WorldProgress) and the runner's record (its counters, the
// settle monitor, the observers' accumulators and the byte lengths of the CSVs at that
// step). Written atomically every outputs.checkpoint_every steps and when a run is
// stopped by SIGINT or SIGTERM (run/stop_request.hpp); removed when the run ends.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "ratchet/world/world.hpp"

namespace ratchet {

inline constexpr const char* kCheckpointFileName = "checkpoint.state";

// Writes DIR/checkpoint.state for the world's current state; `run` is the runner's
// record (run/runner.cpp), stored as it is.
void write_checkpoint(const std::string& dir, const World& world, const nlohmann::json& run);

// A checkpoint read back: the scene rebuilt from the scene as run, checked against the
// file's key (the scene hash).
struct ResumePoint {
  std::string path;
  SceneDef scene;
  State state;
  WorldProgress progress;
  nlohmann::json run;
};

// Reads DIR/checkpoint.state. Throws StateFileError (io/state_file.hpp) naming the file
// when it is missing, damaged, of another engine (version or source hash,
// run_output.hpp other_engine) or not a checkpoint, and
// SceneError when its scene no longer builds.
ResumePoint read_checkpoint(const std::string& dir);

// Puts a world fresh from point.scene at the checkpoint: its state and progress.
void resume_world(World& world, const ResumePoint& point);

// The world's progress (stage, step count, solver totals, phase timers) as a checkpoint
// stores it, and back (std::runtime_error for timers of another engine); the pour's
// checkpoint (run/pour_checkpoint.hpp) stores it the same way.
nlohmann::json progress_json(const WorldProgress& p);
WorldProgress progress_from_json(const nlohmann::json& j);

}  // namespace ratchet
