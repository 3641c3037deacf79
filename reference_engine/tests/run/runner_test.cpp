// run_world: every step once, rows at the asked-for steps and the last one, the
// summary in run.json, and RunError (no run.json) when the state stops being finite.
#include "ratchet/run/runner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/test_files.hpp"

namespace ratchet {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

using test::lines_of;

// Two spheres falling onto a floor: 10 steps.
SceneDef falling() {
  return build_scene(json::parse(R"({
    "name": "fall", "time": {"dt": 0.01, "duration": 0.1},
    "container": {"type": "planes", "planes": [{"normal": [0, 0, 1], "point": [0, 0, 0]}]},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 0.6]},
                             {"shape": "sphere", "radius": 0.5, "position": [2, 0, 3]}]},
    "outputs": {"timeseries_every": 3, "volume": false}
  })"),
                     "fall.json");
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("ratchet_runner_" + name);
  fs::remove_all(d);
  return d;
}

TEST(RunWorld, StepsToTheEndCallingBackEachStep) {
  World world(falling());
  ASSERT_EQ(world.scene().steps, 10);
  std::vector<std::int64_t> seen;
  const RunResult r = run_world(world, RunOptions{}, [&](const World& w) { seen.push_back(w.state().step); });
  EXPECT_EQ(r.steps, 10);
  ASSERT_EQ(seen.size(), 10u);
  for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], static_cast<std::int64_t>(i + 1));
  EXPECT_LT(world.state().x[1].z(), 3.0);  // it fell
  EXPECT_TRUE(r.settle.is_null());         // no thermal section, no settle stage
}

TEST(RunWorld, RowsAtEveryNthStepAndTheLast) {
  const fs::path d = scratch("rows");
  World world(falling());
  RunOptions opt;
  opt.out_dir = d.string();
  const RunResult r = run_world(world, opt);
  std::vector<std::string> steps;
  for (const std::string& row : lines_of(d / "timeseries.csv")) steps.push_back(row.substr(0, row.find(',')));
  EXPECT_EQ(steps, (std::vector<std::string>{"step", "0", "3", "6", "9", "10"}));
  EXPECT_EQ(lines_of(d / "bodies.csv").size(), 1u + 2u * 2u);  // first and last snapshots
  std::ifstream in(d / "run.json");
  const json meta = json::parse(in);
  EXPECT_EQ(meta.at("status"), "completed");
  EXPECT_EQ(meta.at("steps"), 10);
  EXPECT_EQ(meta.at("summary"), r.summary);
  EXPECT_EQ(meta.at("warnings"), json::array());  // every step converged
  EXPECT_EQ(meta.at("summary").at("unconverged_fraction"), 0.0);
  fs::remove_all(d);
}

// A sphere that outgrows the fixed walls around it has no rigid solution: its capped
// steps are solved again as jams, counted in run.json and named in a warning
// (docs/method.md, "Infeasible jam").
TEST(RunWorld, JammedStepsAreCountedAndNamedInRunJson) {
  const fs::path d = scratch("jam");
  json scene = json::parse(R"({
    "name": "jam", "time": {"dt": 0.001, "duration": 3.0},
    "effects": {"gravity": false},
    "solver": {"tolerance": 1e-8, "max_iterations": 200},
    "thermal": {"T0": 0, "T1": 100, "heat_time": 2, "hold_time": 1, "cool_time": 2, "cycles": 1,
                "alpha_p": 1e-4, "alpha_c": 0},
    "container": {"type": "planes", "planes": [{"normal": [1, 0, 0], "point": [-1.002, 0, 0]},
                                               {"normal": [-1, 0, 0], "point": [1.002, 0, 0]}]},
    "particles": {"bodies": [{"shape": "sphere", "radius": 1.0, "position": [0, 0, 0]}]},
    "outputs": {"volume": false}
  })");
  World world(build_scene(scene, "jam.json"));
  RunOptions opt;
  opt.out_dir = d.string();
  const RunResult r = run_world(world, opt);
  std::ifstream in(d / "run.json");
  const json meta = json::parse(in);
  const auto jammed = meta.at("counters").at("jammed_steps").get<long long>();
  EXPECT_GT(jammed, 0);  // from T = 20 (t = 0.4) the sphere is wider than the gap
  EXPECT_LE(jammed, meta.at("counters").at("unconverged_steps").get<long long>());
  bool named = false;
  for (const auto& w : r.warnings) named |= w.get<std::string>().find(std::to_string(jammed) + " of these steps were jams") != std::string::npos;
  EXPECT_TRUE(named) << meta.at("warnings").dump();
  fs::remove_all(d);
}

// The iteration cap is meant to be out of reach: a run whose steps stop there says so in
// run.json, with the count and the first such step (docs/output-format.md).
TEST(RunWorld, StepsStoppedAtTheCapAreAWarningInRunJson) {
  const fs::path d = scratch("cap");
  json scene = json::parse(R"({
    "name": "stack", "time": {"dt": 0.01, "duration": 0.05},
    "solver": {"max_iterations": 1, "tolerance": 1e-12},
    "container": {"type": "planes", "planes": [{"normal": [0, 0, 1], "point": [0, 0, 0]}]},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 0.5]},
                             {"shape": "sphere", "radius": 0.5, "position": [0, 0, 1.5]},
                             {"shape": "sphere", "radius": 0.5, "position": [0, 0, 2.5]}]},
    "outputs": {"volume": false}
  })");
  World world(build_scene(scene, "stack.json"));
  RunOptions opt;
  opt.out_dir = d.string();
  const RunResult r = run_world(world, opt);
  ASSERT_EQ(r.warnings.size(), 1u);
  const std::string w = r.warnings[0].get<std::string>();
  EXPECT_NE(w.find("5 of 5 steps stopped at solver.max_iterations = 1"), std::string::npos) << w;
  EXPECT_NE(w.find("the first at step 1"), std::string::npos) << w;
  std::ifstream in(d / "run.json");
  const json meta = json::parse(in);
  EXPECT_EQ(meta.at("warnings"), r.warnings);
  EXPECT_EQ(meta.at("counters").at("unconverged_steps"), 5);
  EXPECT_EQ(meta.at("counters").at("jammed_steps"), 0);  // one sweep has no second half to grow over
  // The summary (and so a sweep's summary.csv) carries it beside the observables.
  EXPECT_EQ(meta.at("summary").at("unconverged_steps"), 5);
  EXPECT_EQ(meta.at("summary").at("unconverged_fraction"), 1.0);
  fs::remove_all(d);
}

TEST(RunWorld, NonFiniteStateIsARunError) {
  const fs::path d = scratch("nan");
  World world(falling());
  world.mutable_state().v[1] = Vec3(0.0, 0.0, std::nan(""));
  RunOptions opt;
  opt.out_dir = d.string();
  EXPECT_THROW(run_world(world, opt), RunError);
  // Kept, marked failed: the run does not look complete, and says why.
  const json meta = json::parse(std::ifstream(d / "run.json"));
  EXPECT_EQ(meta.at("status"), "failed");
  EXPECT_NE(meta.at("error").get<std::string>().find("non-finite at step 1"), std::string::npos);
  EXPECT_EQ(lines_of(d / "timeseries.csv").size(), 2u);  // header and step 0: what was written
  fs::remove_all(d);
}

// Runs `world` into `d`, which must stop at step 1 as unphysical with every text of
// `expected` in its message; the folder keeps run.json marked failed after 1 step.
void expect_unphysical_at_step_1(World& world, const fs::path& d, const std::vector<std::string>& expected) {
  RunOptions opt;
  opt.out_dir = d.string();
  try {
    run_world(world, opt);
    ADD_FAILURE() << "the run completed";
  } catch (const RunError& e) {
    const std::string what = e.what();
    for (const std::string& text : expected) EXPECT_NE(what.find(text), std::string::npos) << what;
  }
  const json meta = json::parse(std::ifstream(d / "run.json"));
  EXPECT_EQ(meta.at("status"), "failed");
  EXPECT_EQ(meta.at("steps"), 1);
  fs::remove_all(d);
}

// A step far too large for the speed: the sphere passes the floor between two
// detections (10 per step against the contact margin 0.05) and ends 5.01 below it
// (5 - h (100 + g h)).
TEST(RunWorld, ABodyOutsideTheContainerStopsTheRunNamingIt) {
  World world(build_scene(json::parse(R"({
    "name": "tunnel", "time": {"dt": 0.1, "duration": 1.0},
    "container": {"type": "planes", "planes": [{"normal": [0, 0, 1], "point": [0, 0, 0]}]},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 5], "velocity": [0, 0, -100]},
                             {"shape": "sphere", "radius": 0.5, "position": [3, 0, 0.5]}]}
  })"), "tunnel.json"));
  expect_unphysical_at_step_1(world, scratch("outside"),
                              {"tunnel.json: the state became unphysical at step 1",
                               "1 body outside the container: body 0 (centre 5.01 behind wall 0, size 0.5)"});
}

// A body thrown across the room: 60 per step against its radius 0.5, above the floor, so
// neither outside the container nor overlapping; but it could pass through anything of
// its size between two detections. A diverging solve ends the same way before a NaN.
TEST(RunWorld, ABodyFasterThanItsSizePerStepStopsTheRunNamingIt) {
  World world(build_scene(json::parse(R"({
    "name": "thrown", "time": {"dt": 0.1, "duration": 1.0},
    "container": {"type": "planes", "planes": [{"normal": [0, 0, 1], "point": [0, 0, 0]}]},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 5], "velocity": [600, 0, 0]}]}
  })"), "thrown.json"));
  expect_unphysical_at_step_1(world, scratch("fast_body"),
                              {"thrown.json: the state became unphysical at step 1", "body 0 moved 60 in one step",
                               "bounding radius 0.5"});
}

// Within the bounds, the same scene with a sane step runs to the end.
TEST(RunWorld, TheSameFallWithASmallStepCompletes) {
  World world(build_scene(json::parse(R"({
    "name": "fall", "time": {"dt": 0.001, "duration": 0.2},
    "container": {"type": "planes", "planes": [{"normal": [0, 0, 1], "point": [0, 0, 0]}]},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 5], "velocity": [0, 0, -30]}]}
  })"), "fall.json"));
  RunResult r;
  EXPECT_NO_THROW(r = run_world(world, {}));
  EXPECT_GT(world.state().x[0].z(), 0.4);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.dump();  // 0.03 per step, within the margin 0.05
}

// Ten times the step: 0.3 per step against the margin 0.05. The sphere still lands (its
// overlap stays below its size), and the run says the step outran the margin.
TEST(RunWorld, AStepThatOutrunsTheContactMarginIsAWarning) {
  World world(build_scene(json::parse(R"({
    "name": "fast", "time": {"dt": 0.01, "duration": 0.5},
    "container": {"type": "planes", "planes": [{"normal": [0, 0, 1], "point": [0, 0, 0]}]},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 5], "velocity": [0, 0, -30]}]}
  })"), "fast.json"));
  const RunResult r = run_world(world, {});
  ASSERT_EQ(r.warnings.size(), 1u);
  const std::string w = r.warnings[0].get<std::string>();
  EXPECT_NE(w.find("a body moved farther than solver.contact_margin = 0.05 per step (at most 0.30"),
            std::string::npos) << w;
  EXPECT_NE(w.find("the first at step 1)"), std::string::npos) << w;
}

// A container that cools in one step moves its walls farther than the margin: flagged as
// the fast body is (the contacts against it may be found only after they overlap).
TEST(RunWorld, AWallThatOutrunsTheContactMarginIsAWarning) {
  World world(build_scene(json::parse(R"({
    "name": "fast_wall", "time": {"dt": 0.01},
    "container": {"type": "cone", "bottom_radius": 5.0, "opening_angle_deg": 0, "segments": 8},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 0.5]}]},
    "thermal": {"start_time": 0.1, "heat_time": 0.01, "hold_time": 0.1, "cool_time": 0.5, "cycles": 1,
                "alpha_p": 0, "alpha_c": 1e-3}
  })"), "fast_wall.json"));
  const RunResult r = run_world(world, {});
  ASSERT_EQ(r.warnings.size(), 1u) << r.warnings.dump();
  const std::string w = r.warnings[0].get<std::string>();
  // Heating in one step moves the side walls by alpha_c dT r = 1e-3 x 100 x 5 = 0.5;
  // cooling over 50 steps by 0.01 per step, below the margin.
  EXPECT_NE(w.find("in 1 of "), std::string::npos) << w;
  EXPECT_NE(w.find("a container wall moved along its normal farther than solver.contact_margin = 0.05 per step "
                   "(at most 0.5"),
            std::string::npos)
      << w;
}

}  // namespace
}  // namespace ratchet
