// One observable accumulated over a run (docs/output-format.md): what RunObservers
// (run/observers.hpp) asks of each, so that it names none of them. An accumulator acts
// on the cycle clock's ticks after every step, and supplies its own columns of
// timeseries.csv and cycles.csv, its part of run.json's summary and its own files, and
// its record in a checkpoint. Every method but after_step defaults to "nothing".
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/run/cycle_clock.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

// What an accumulator is made from (run/accumulators.hpp).
struct ObserverSetup {
  const World& world;       // at the run's first state, or at the checkpoint's
  const CycleClock& clock;  // not yet restored when resuming
  const std::string& out_dir;  // empty: no files
  bool resuming = false;    // a resumed run: the interrupted run wrote the first state's files
};

// The end of a run, as finish() sees it.
struct RunEnd {
  const World& world;
  const CycleClock& clock;
  const std::string& out_dir;  // empty: no files
};

class Accumulator {
 public:
  virtual ~Accumulator() = default;

  // After every step, with the clock's tick for the new state.
  virtual void after_step(const World& world, const ClockTick& tick) = 0;

  // timeseries.csv: the names of this accumulator's columns (once), and their values
  // for the current state (as many, in the same order; on every row).
  virtual void timeseries_columns(std::vector<std::string>& /*names*/) const {}
  virtual void timeseries_values(const World& /*world*/, std::vector<double>& /*values*/) const {}

  // cycles.csv: the names of its columns, and the cells of the row of `cycle` (as many,
  // formatted; every cycle reached has a row).
  virtual void cycle_columns(std::vector<std::string>& /*names*/) const {}
  virtual void cycle_cells(int /*cycle*/, std::vector<std::string>& /*cells*/) const {}

  // End of the run: its entries of the summary (run.json) and its own files.
  virtual void finish(const RunEnd& /*end*/, nlohmann::json& /*summary*/) const {}

  // A checkpoint's record (run/checkpoint.hpp; null: nothing to keep), and its restore.
  virtual nlohmann::json save() const { return nullptr; }
  virtual void restore(const nlohmann::json& /*saved*/) {}
};

}  // namespace ratchet
