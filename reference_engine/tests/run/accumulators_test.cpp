// The seam of a new per-cycle observable: a throwaway accumulator, registered in one
// line (a ScopedAccumulator) and named nowhere in the engine, gets its column in
// cycles.csv and its record in a checkpoint, and leaves no trace once the guard is gone.
#include "ratchet/run/accumulators.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "ratchet/run/observers.hpp"
#include "ratchet/run/runner.hpp"
#include "support/test_files.hpp"

namespace ratchet {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The states of each cycle.
class StepsPerCycle final : public Accumulator {
 public:
  void after_step(const World&, const ClockTick& tick) override {
    if (tick.cycle < 0) return;
    const std::size_t k = static_cast<std::size_t>(tick.cycle);
    if (steps_.size() <= k) steps_.resize(k + 1, 0);
    ++steps_[k];
  }
  void cycle_columns(std::vector<std::string>& names) const override { names.push_back("steps_in_cycle"); }
  void cycle_cells(int cycle, std::vector<std::string>& cells) const override {
    cells.push_back(std::to_string(steps_.at(static_cast<std::size_t>(cycle))));
  }
  json save() const override { return steps_; }
  void restore(const json& saved) override { steps_ = saved.get<std::vector<int>>(); }

 private:
  std::vector<int> steps_;
};

// Two cycles of 0.3 = 30 steps after a rest of 10 steps: 70 steps.
SceneDef two_short_cycles() {
  return build_scene(json::parse(R"({
    "name": "short", "time": {"dt": 0.01},
    "container": {"type": "cone", "bottom_radius": 2.0},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 0.5]}]},
    "thermal": {"start_time": 0.1, "heat_time": 0.1, "hold_time": 0.05, "cool_time": 0.1, "cycles": 2}
  })"),
                     "short.json");
}

using test::lines_of;

// The rows of cycles.csv of a whole run of two_short_cycles().
std::vector<std::string> cycles_csv_of_a_run() {
  const fs::path d = test::fresh_dir("ratchet_accumulators");
  World world(two_short_cycles());
  RunOptions opt;
  opt.out_dir = d.string();
  run_world(world, opt);
  std::vector<std::string> rows = lines_of(d / "cycles.csv");
  fs::remove_all(d);
  return rows;
}

TEST(Accumulators, TheEnginesComeFirstInColumnOrderThenTheRegistered) {
  const ScopedAccumulator registered = scoped_accumulator<StepsPerCycle>("steps_per_cycle");
  const std::vector<AccumulatorEntry>& list = accumulator_entries();
  ASSERT_GE(list.size(), 2u);
  EXPECT_STREQ(list.front().key, "peaks");  // cycles.csv: peak_pressure right after cycle
  EXPECT_STREQ(list.back().key, "steps_per_cycle");
}

TEST(Accumulators, ARegisteredObservableAppearsInCyclesCsv) {
  const ScopedAccumulator registered = scoped_accumulator<StepsPerCycle>("steps_per_cycle");
  const std::vector<std::string> rows = cycles_csv_of_a_run();
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0],
            "cycle,peak_pressure,t_peak,V_over_V0_end_heating,V_over_V0_end_cooling,contacts_mean,iterations_mean,"
            "unconverged_steps,steps_in_cycle");
  for (const std::string& row : {rows[1], rows[2]}) EXPECT_EQ(row.substr(row.rfind(',') + 1), "30") << row;
}

// Saved after 45 steps (10 before cycling, 30 of cycle 0, 5 of cycle 1), restored into
// the observers of a resumed run, which count cycle 1's other 25.
TEST(Accumulators, ARegisteredObservableKeepsItsRecordInACheckpoint) {
  const ScopedAccumulator registered = scoped_accumulator<StepsPerCycle>("steps_per_cycle");
  World world(two_short_cycles());
  RunObservers before(world, "");
  for (int k = 0; k < 45; ++k) {
    world.step();
    before.after_step(world);
  }
  const json saved = before.save();
  ASSERT_TRUE(saved.contains("steps_per_cycle"));
  EXPECT_EQ(saved.at("steps_per_cycle"), json::array({30, 5}));
  const fs::path d = test::fresh_dir("ratchet_accumulators");
  RunObservers after(world, d.string(), saved);
  while (world.state().step < world.scene().steps) {
    world.step();
    after.after_step(world);
  }
  after.finish(world);
  const std::vector<std::string> rows = lines_of(d / "cycles.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[2].substr(rows[2].rfind(',') + 1), "30");
  fs::remove_all(d);
}

// Registered for one scope only: after it, the list is the engine's again and a run has
// neither the column nor the checkpoint record.
TEST(Accumulators, AnObservableIsGoneWithItsGuard) {
  const std::size_t engines = accumulator_entries().size();
  {
    const ScopedAccumulator registered = scoped_accumulator<StepsPerCycle>("steps_per_cycle");
    ASSERT_EQ(accumulator_entries().size(), engines + 1);
  }
  ASSERT_EQ(accumulator_entries().size(), engines);
  const std::vector<std::string> rows = cycles_csv_of_a_run();
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].find("steps_in_cycle"), std::string::npos) << rows[0];
  EXPECT_EQ(rows[0].substr(rows[0].rfind(',') + 1), "unconverged_steps");
  World world(two_short_cycles());
  EXPECT_FALSE(RunObservers(world, "").save().contains("steps_per_cycle"));
}

}  // namespace
}  // namespace ratchet
