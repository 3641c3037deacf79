// The observables a scene asks for (docs/output-format.md), gathered during a run: a
// cycle clock (run/cycle_clock.hpp) says where the run is in its thermal protocol, and
// the accumulators of run/accumulators.hpp act on its ticks, each supplying its columns,
// summary entries, files and checkpoint record (run/accumulator.hpp); the measurements
// themselves are the pure functions of observe/. Nothing is computed that outputs does
// not ask for.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/run/accumulator.hpp"
#include "ratchet/run/cycle_clock.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

class RunObservers {
 public:
  // At the run's first state; out_dir empty: no files.
  RunObservers(const World& world, std::string out_dir);
  // A resumed run (run/checkpoint.hpp): at the checkpoint's state, with its record
  // (save()); writes nothing for that state, which the interrupted run wrote.
  RunObservers(const World& world, std::string out_dir, const nlohmann::json& saved);

  // Extra timeseries columns, in this order (names, then values for the current state).
  const std::vector<std::string>& extra_columns() const { return columns_; }
  void extra_values(const World& world, std::vector<double>& values) const;

  // After every step.
  void after_step(const World& world);

  // End of the run: writes cycles.csv and the accumulators' files (displacement_<a>_<b>.csv,
  // stage_fields.csv, wall_profile.csv) and returns the summary (P_max, V/V0, W_rms per
  // window) for run.json.
  nlohmann::json finish(const World& world);

  // Everything the accumulators hold, for a checkpoint.
  nlohmann::json save() const;

 private:
  struct Held {
    const char* key;  // its record in a checkpoint; nullptr: none
    std::unique_ptr<Accumulator> accumulator;
  };

  void make_accumulators(const World& world, bool resuming);
  void write_cycles(const std::string& path) const;

  const SceneDef& scene_;
  std::string out_dir_;
  std::int64_t first_step_;    // a run from a packing starts at the packing's step
  std::vector<std::string> columns_;
  CycleClock clock_;
  std::vector<Held> accumulators_;  // in the order of run/accumulators.hpp
};

}  // namespace ratchet
