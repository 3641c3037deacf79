// Where a run is in its thermal protocol (docs/output-format.md, "Thermal cycles, stage
// ends and snapshots"): the settle stage, the start of cycling, the cycle of each state
// and the stage marks a step crosses. The accumulators of run/observers.hpp act on its
// ticks and keep no clock of their own.
#pragma once

#include <nlohmann/json.hpp>

#include "ratchet/run/time_marks.hpp"
#include "ratchet/scene/scene.hpp"

namespace ratchet {

// Stage marks crossed by the step from t_prev to t (several at once when a hold has
// zero length).
struct StageEnds {
  bool heating = false, cooling = false, cycle = false;
};

// What one state means for the protocol. All false / -1 in a run without thermal cycles.
struct ClockTick {
  double t_prev = 0.0, t = 0.0;  // the previous state's time and this one's
  bool settling = false;         // the settle stage is still on at this state
  bool settle_ended = false;     // a settle section's stage ended at this state
  bool before_cycling = false;   // cycling had not started at the previous state
  bool cycling_starts = false;   // this state is the start of cycling (once per run)
  int cycle = -1;                // the cycle this state belongs to, or -1 outside the cycles
  StageEnds ends;                // marks crossed since the previous state (cycle >= 0 only)
};

class CycleClock {
 public:
  // At the run's first state: time t0, `settling` as World::settling().
  CycleClock(const SceneDef& scene, double t0, bool settling);

  bool thermal() const { return thermal_; }
  // The first state already is the start of cycling or past it (start_time 0, or a
  // packing that ends at start_time).
  bool started_at_first_state() const { return started_at_first_; }
  int cycles_reached() const { return cycles_reached_; }

  // After each step, with the new state's time and World::settling().
  ClockTick tick(double t, bool settling);

  // Marks crossed between t_prev and t.
  StageEnds stage_ends(double t_prev, double t) const;

  // A checkpoint's record of this accumulator (run/checkpoint.hpp), and its restore.
  nlohmann::json save() const;
  void restore(const nlohmann::json& j);

 private:
  const SceneDef& scene_;
  bool thermal_ = false;
  bool started_ = false;         // the start of cycling has been reached
  bool started_at_first_ = false;
  bool settle_pending_ = false;  // a settle section's stage has not ended yet
  double t_prev_ = 0.0;
  int cycles_reached_ = 0;
};

}  // namespace ratchet
