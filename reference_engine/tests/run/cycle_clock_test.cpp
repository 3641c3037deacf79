// The cycle clock: the start of cycling once, the cycle of each state, the stage marks
// within round-off, the end of a settle section's stage, and silence without cycles.
#include "ratchet/run/cycle_clock.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace ratchet {
namespace {

using nlohmann::json;

// Cycle time L = 1 + 0.5 + 1 + 0.5 = 3 from start_time 1; h = 0.25 is exact in binary.
SceneDef two_cycles() {
  return build_scene(json::parse(R"({
    "name": "clock", "time": {"dt": 0.25},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 0.5]}]},
    "thermal": {"start_time": 1.0, "heat_time": 1.0, "hold_time": 0.5, "cool_time": 1.0, "cycles": 2}
  })"),
                     "clock.json");
}

TEST(CycleClock, MarksEachStageOnceAtItsStep) {
  const SceneDef s = two_cycles();
  CycleClock clock(s, 0.0, false);
  ASSERT_TRUE(clock.thermal());
  EXPECT_FALSE(clock.started_at_first_state());
  std::vector<double> starts, heating, cooling, cycle_ends;
  for (int k = 1; k <= 36; ++k) {
    const double t = 0.25 * k;
    const ClockTick tick = clock.tick(t, false);
    EXPECT_EQ(tick.t, t);
    EXPECT_EQ(tick.t_prev, t - 0.25);
    EXPECT_EQ(tick.before_cycling, t <= 1.0) << t;
    EXPECT_EQ(tick.cycle, t <= 1.0 || t > 7.0 ? -1 : t <= 4.0 ? 0 : 1) << t;
    if (tick.cycling_starts) starts.push_back(t);
    if (tick.ends.heating) heating.push_back(t);
    if (tick.ends.cooling) cooling.push_back(t);
    if (tick.ends.cycle) cycle_ends.push_back(t);
  }
  EXPECT_EQ(starts, (std::vector<double>{1.0}));
  EXPECT_EQ(heating, (std::vector<double>{2.0, 5.0}));
  EXPECT_EQ(cooling, (std::vector<double>{3.5, 6.5}));
  EXPECT_EQ(cycle_ends, (std::vector<double>{4.0, 7.0}));
  EXPECT_EQ(clock.cycles_reached(), 2);
}

// t is accumulated, so a mark is reached a little below it: within 1e-4 h it counts,
// and the next step does not count it again.
TEST(CycleClock, AMarkJustBelowItsStepCountsOnce) {
  const SceneDef s = two_cycles();
  CycleClock clock(s, 1.75, false);
  EXPECT_TRUE(clock.started_at_first_state());
  const ClockTick a = clock.tick(2.0 - 1e-6 * 0.25, false);
  EXPECT_TRUE(a.ends.heating);
  EXPECT_FALSE(a.cycling_starts);
  EXPECT_FALSE(clock.tick(2.25, false).ends.heating);
  CycleClock other(s, 1.75, false);
  EXPECT_FALSE(other.tick(2.0 - 1e-3 * 0.25, false).ends.heating);  // too far below: next step
  EXPECT_TRUE(other.tick(2.25, false).ends.heating);
}

TEST(CycleClock, SettleStageEndsOnce) {
  const SceneDef s = two_cycles();
  CycleClock clock(s, 0.0, true);
  EXPECT_FALSE(clock.tick(0.25, true).settle_ended);
  const ClockTick end = clock.tick(0.5, false);
  EXPECT_TRUE(end.settle_ended);
  EXPECT_FALSE(end.settling);
  EXPECT_FALSE(clock.tick(0.75, false).settle_ended);
}

TEST(CycleClock, NoCyclesNoTicks) {
  SceneDef s = two_cycles();
  s.thermal.cycles = 0;
  CycleClock clock(s, 0.0, true);
  EXPECT_FALSE(clock.thermal());
  for (int k = 1; k <= 30; ++k) {
    const ClockTick tick = clock.tick(0.25 * k, false);
    EXPECT_FALSE(tick.settle_ended || tick.cycling_starts || tick.before_cycling || tick.ends.heating);
    EXPECT_EQ(tick.cycle, -1);
  }
  EXPECT_EQ(clock.cycles_reached(), 0);
}

}  // namespace
}  // namespace ratchet
