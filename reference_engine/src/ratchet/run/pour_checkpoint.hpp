// A pour that outlives its session (docs/cli.md, "Stopping and resuming"): the settle
// stage of `ratchet pack` and of a sweep's packings writes PACKING.pour-checkpoint every
// outputs.checkpoint_every steps and when SIGINT or SIGTERM stops it; the same command run
// again goes on from it, bit for bit the pour never stopped, and removes it once the
// packing is written. The file is a state file (io/state_file.hpp) keyed by the packing
// key, with the world's progress and the settle monitor. A checkpoint of another pour
// (another packing key), of another engine, or damaged is not used: the pour starts over.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "ratchet/world/world.hpp"

namespace ratchet {

// Where the pour that makes the packing file `packing_path` keeps its checkpoint.
std::string pour_checkpoint_path(const std::string& packing_path);

// Where and how often a pour writes its checkpoint (settle_world, run/packing.hpp).
struct PourCheckpointing {
  std::string path;  // empty: no checkpoint, a stop request ends nothing early
  int every = 0;     // steps between periodic checkpoints; 0: only when stopped
};

// The checkpointing of the pour that makes `packing_path` for `scene`: next to the packing,
// every outputs.checkpoint_every steps.
PourCheckpointing pour_checkpointing(const std::string& packing_path, const SceneDef& scene);

// Removes the pour's checkpoint, if any (the packing is written, or the pour failed).
void remove_pour_checkpoint(const PourCheckpointing& checkpoints);

// Writes the pour's checkpoint atomically; `monitor` is SettleMonitor::save().
void write_pour_checkpoint(const std::string& path, const World& world, const nlohmann::json& monitor);

// The checkpoint at `path`, if it is a pour checkpoint of this world's packing key by this
// engine: puts the world (fresh from its scene) at it and returns the saved monitor.
// Otherwise returns null and, when a file was there, says in *why_not why it is not used.
nlohmann::json resume_pour(const std::string& path, World& world, std::string* why_not);

}  // namespace ratchet
