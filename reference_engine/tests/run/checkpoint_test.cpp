// Checkpoints and resuming (run/checkpoint.hpp, run/stop_request.hpp): a run stopped by a
// request, or "killed" (its folder copied as it stood on disk at some step, as SIGKILL
// would leave it), and resumed from its checkpoint writes the same bytes as the run that
// never stopped: every CSV (the wall-clock time_* columns aside), the VTK files and
// run.json (its timings aside). The pytest scripts/tests/test_resume.py does the same with
// real signals on the ratchet binary.
#include "ratchet/run/checkpoint.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>

#include "../support/test_files.hpp"
#include "ratchet/io/state_file.hpp"
#include "ratchet/run/packing.hpp"
#include "ratchet/run/run_output.hpp"
#include "ratchet/run/runner.hpp"
#include "ratchet/run/stop_request.hpp"

namespace ratchet {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::without_timing_columns;
using test::fresh_dir;
using test::read_text;

// A small bed through every stage and observable: pour, settle section, settled wall
// profile, two cycles with V/V0, peaks, segment forces, displacement windows and stage
// fields, wall profile and VTK (every 400 steps and at stage ends); compliant Anderson
// sweeps as the standard tier. 40 bodies, 2100 steps or so, about a second.
json bed() {
  return json::parse(R"({
    "name": "resumable", "seed": 5, "time": {"dt": 0.004},
    "solver": {"tolerance": 1e-4, "max_iterations": 2000, "acceleration": "anderson", "compliance": 0.1},
    "container": {"type": "cone", "bottom_radius": 3.0, "opening_angle_deg": 4.0, "segments": 8},
    "particles": {"generate": {"count": 40, "shape": "polyhedron", "vertices": 12, "radius_range": [0.3, 0.5]}},
    "settle": {"ke_ratio": 1e-3, "max_time": 10.0},
    "thermal": {"start_time": 1.0, "heat_time": 1.0, "hold_time": 0.5, "cool_time": 1.0, "cycles": 2,
                "alpha_p": 1e-4, "alpha_c": 1e-3},
    "outputs": {"timeseries_every": 7, "bodies_every": 300, "volume": true, "segment_forces": true,
                "steady_cycles": [1, 1], "pressure_window": 0.2,
                "displacement": {"cell": 1.0, "windows": [[0, 1], [0, 2]], "stages": true},
                "wall_profile_bins": 3,
                "settled_profile_time": 0.5, "vtk_cycles": [1], "vtk_every": 400, "checkpoint_every": 250}
  })");
}


// run.json without what a clock and the invocation decide: the timings and the
// provenance (date, host, command line; run/provenance.hpp). A resumed run's provenance
// lists its resumes, and is the whole run's otherwise.
json without_timings(json j) {
  j.erase("wall_seconds");
  for (auto& p : j["phases"]) p.erase("seconds");
  EXPECT_TRUE(j.at("provenance").at("date_utc").is_string());
  j.erase("provenance");
  return j;
}

// Every file of `a` is in `b` with the same contents, and no more files are in `b`.
void expect_same_outputs(const fs::path& a, const fs::path& b) {
  std::vector<fs::path> files_a, files_b;
  for (const auto& e : fs::recursive_directory_iterator(a))
    if (e.is_regular_file()) files_a.push_back(fs::relative(e.path(), a));
  for (const auto& e : fs::recursive_directory_iterator(b))
    if (e.is_regular_file()) files_b.push_back(fs::relative(e.path(), b));
  std::sort(files_a.begin(), files_a.end());
  std::sort(files_b.begin(), files_b.end());
  EXPECT_EQ(files_a, files_b);
  for (const fs::path& f : files_a) {
    const std::string x = read_text(a / f), y = read_text(b / f);
    if (f == "run.json")
      EXPECT_EQ(without_timings(json::parse(x)), without_timings(json::parse(y)));
    else if (f == "timeseries.csv")
      EXPECT_EQ(without_timing_columns(x), without_timing_columns(y));
    else
      EXPECT_TRUE(x == y) << f << " differs";
  }
}

RunResult run_fresh(const SceneDef& scene, const fs::path& dir, const std::function<void(const World&)>& each = {}) {
  World world(scene);
  RunOptions opt;
  opt.out_dir = dir.string();
  return run_world(world, opt, each);
}

RunResult resume(const fs::path& dir) {
  const ResumePoint point = read_checkpoint(dir.string());
  World world(point.scene);
  resume_world(world, point);
  RunOptions opt;
  opt.out_dir = dir.string();
  opt.resume = point.run;
  return run_world(world, opt);
}

// The run never stopped, made once per test program (CTest runs each test in a process
// of its own: each makes its own, in a folder of its own).
class Resume : public ::testing::Test {
 protected:
  void SetUp() override {
    reference_ = fresh_dir("ratchet_checkpoint_reference");
    steps_ = run_fresh(build_scene(bed(), "bed.json"), reference_).steps;
  }
  fs::path reference_;
  std::int64_t steps_ = 0;
};

// The stop points below are steps of this run: the settle stage ends near step 2004 (as
// measured; 1967 before the colour order of the sweep), then come 250 steps of rest whose
// last 125 make the settled wall profile, and two cycles of 750 steps each, to step 3754.
TEST_F(Resume, TheReferenceRunCoversSettleAndCyclesAndLeavesNoCheckpoint) {
  const json run = json::parse(read_text(reference_ / "run.json"));
  const std::int64_t settled = run.at("settle").at("step_end").get<std::int64_t>();
  EXPECT_GT(settled, 600);   // after the stop and kill points in the settle stage
  EXPECT_LT(settled, 2150 - 125);  // the stop and kill points 2150, 2160 lie in the settled-profile window
  EXPECT_EQ(steps_, settled + 250 + 2 * 750);
  EXPECT_EQ(run.at("status"), "completed");
  EXPECT_EQ(run.at("summary").at("cycles_completed"), 2);
  EXPECT_FALSE(fs::exists(reference_ / kCheckpointFileName));  // removed at the end
  EXPECT_TRUE(fs::exists(reference_ / "displacement_0_2.csv"));
  // Stage fields of both cycles: the stops below fall in cycle 0's heating and cycle 1's
  // cooling, so the resumed runs carry kept positions and rows through the checkpoint.
  const auto stages = test::lines_of(reference_ / "stage_fields.csv");
  ASSERT_GT(stages.size(), 2u);
  EXPECT_EQ(stages.back().substr(0, 2), "1,");
  EXPECT_TRUE(fs::exists(reference_ / "wall_profile.csv"));
}

// A stop request (what SIGINT and SIGTERM do) after step k: run.json says interrupted,
// the CSVs stay .partial, and the resumed run ends as the reference.
class StopAndResume : public Resume, public ::testing::WithParamInterface<std::int64_t> {};

TEST_P(StopAndResume, GivesTheBytesOfTheRunThatNeverStopped) {
  const std::int64_t stop_at = GetParam();
  const fs::path d = fresh_dir("ratchet_checkpoint");
  const SceneDef scene = build_scene(bed(), "bed.json");
  try {
    run_fresh(scene, d, [&](const World& w) {
      if (w.state().step == stop_at) request_stop(SIGTERM);
    });
    clear_stop_request();
    FAIL() << "the run did not stop";
  } catch (const RunInterrupted& e) {
    clear_stop_request();
    EXPECT_EQ(e.signal, SIGTERM);
    EXPECT_NE(std::string(e.what()).find("after step " + std::to_string(stop_at)), std::string::npos) << e.what();
  }
  const json stopped = json::parse(read_text(d / "run.json"));
  EXPECT_EQ(stopped.at("status"), "interrupted");
  EXPECT_EQ(stopped.at("signal"), "SIGTERM");
  EXPECT_EQ(stopped.at("steps"), stop_at);
  EXPECT_TRUE(fs::exists(d / "timeseries.csv.partial"));
  EXPECT_FALSE(fs::exists(d / "timeseries.csv"));  // nothing that looks finished
  ASSERT_TRUE(fs::exists(d / kCheckpointFileName));
  EXPECT_EQ(read_state_file((d / kCheckpointFileName).string()).state.step, stop_at);

  const RunResult r = resume(d);
  EXPECT_EQ(r.steps, steps_);
  expect_same_outputs(reference_, d);
}

// In the settle stage, the settled profile's window, cycle 0 (heating) and cycle 1 (cooling).
INSTANTIATE_TEST_SUITE_P(Checkpoint, StopAndResume, ::testing::Values(185, 2150, 2600, 3450));

// SIGKILL: nothing runs at the kill, so what is on disk then is the last periodic
// checkpoint and CSVs that have grown past it (buffered or not). The folder is copied
// as it stands after step k, then resumed.
class KillAndResume : public Resume, public ::testing::WithParamInterface<std::int64_t> {};

TEST_P(KillAndResume, GivesTheBytesOfTheRunThatNeverStopped) {
  const std::int64_t kill_at = GetParam();
  const fs::path live = fresh_dir("ratchet_checkpoint_live"), killed = fresh_dir("ratchet_checkpoint_killed");
  const SceneDef scene = build_scene(bed(), "bed.json");
  run_fresh(scene, live, [&](const World& w) {
    if (w.state().step != kill_at) return;
    fs::remove_all(killed);
    fs::copy(live, killed, fs::copy_options::recursive);
  });
  ASSERT_TRUE(fs::exists(killed / kCheckpointFileName));
  ASSERT_FALSE(fs::exists(killed / "run.json"));
  const std::int64_t checkpoint_step = read_state_file((killed / kCheckpointFileName).string()).state.step;
  EXPECT_LT(checkpoint_step, kill_at);  // the CSVs are ahead of it: they are cut back
  EXPECT_EQ(checkpoint_step % 250, 0);
  resume(killed);
  expect_same_outputs(reference_, killed);
}

// Between checkpoints (every 250 steps): in the settle stage, the settled window,
// cycle 0 and cycle 1.
INSTANTIATE_TEST_SUITE_P(Checkpoint, KillAndResume, ::testing::Values(557, 2160, 2800, 3600));

// With manifold reuse the kept manifolds are part of the state: a run stopped in its
// first heating resumes to the bytes of the run that never stopped. The reuse acts
// (pairs are replayed, and the run differs from one that rebuilds every step).
TEST(Checkpoint, ManifoldReuseResumesToTheSameBytes) {
  json j = bed();
  j["solver"]["manifold_reuse"] = 0.005;
  const SceneDef scene = build_scene(j, "bed.json");
  const fs::path reference = fresh_dir("ratchet_checkpoint_reuse_reference"), d = fresh_dir("ratchet_checkpoint_reuse");
  long replayed = 0;
  run_fresh(scene, reference, [&](const World& w) { replayed += w.stats().manifolds_replayed; });
  EXPECT_GT(replayed, 1000);
  const fs::path rebuilt = fresh_dir("ratchet_checkpoint_rebuilt");
  run_fresh(build_scene(bed(), "bed.json"), rebuilt);
  EXPECT_NE(read_text(reference / "bodies.csv"), read_text(rebuilt / "bodies.csv"));
  constexpr std::int64_t kStopAt = 2600;
  try {
    run_fresh(scene, d, [&](const World& w) {
      if (w.state().step == kStopAt) request_stop(SIGTERM);
    });
    clear_stop_request();
    FAIL() << "the run did not stop";
  } catch (const RunInterrupted&) {
    clear_stop_request();
  }
  EXPECT_FALSE(read_state_file((d / kCheckpointFileName).string()).state.manifolds.empty());
  resume(d);
  expect_same_outputs(reference, d);
}

// A run from a packing keeps the packing's record through a stop.
TEST(Checkpoint, ARunFromAPackingResumesWithThePackingsRecord) {
  const fs::path d = fresh_dir("ratchet_checkpoint");
  const SceneDef scene = build_scene(bed(), "bed.json");
  World pour(scene);
  const json settle = settle_world(pour);
  write_packing((d / "bed.state").string(), pour, settle);
  auto start = [&](const fs::path& out, const std::function<void(const World&)>& each) {
    World world(scene);
    RunOptions opt;
    opt.out_dir = out.string();
    const json meta = load_packing((d / "bed.state").string(), world);
    opt.packing = packing_reference((d / "bed.state").string(), world);
    opt.packing_settle = meta.value("settle", json());
    return run_world(world, opt, each);
  };
  start(d / "whole", {});
  const std::int64_t first = read_state_file((d / "bed.state").string()).state.step;
  try {
    start(d / "stopped", [&](const World& w) {
      if (w.state().step == first + 300) request_stop(SIGINT);
    });
    clear_stop_request();
    FAIL() << "the run did not stop";
  } catch (const RunInterrupted&) {
    clear_stop_request();
  }
  resume(d / "stopped");
  const json whole = json::parse(read_text(d / "whole" / "run.json"));
  ASSERT_FALSE(whole.at("packing").is_null());
  expect_same_outputs(d / "whole", d / "stopped");
  const json resumed = json::parse(read_text(d / "stopped" / "run.json"));
  EXPECT_FALSE(whole.at("provenance").contains("resumed"));
  ASSERT_EQ(resumed.at("provenance").at("resumed").size(), 1u);  // the run started once and was resumed once
  EXPECT_TRUE(resumed.at("provenance").at("resumed").at(0).at("date_utc").is_string());
}

TEST(Checkpoint, ReadingRefusesWhatCannotBeResumedNamingTheFile) {
  const fs::path d = fresh_dir("ratchet_checkpoint");
  try {
    read_checkpoint(d.string());
    FAIL();
  } catch (const StateFileError& e) {
    EXPECT_NE(std::string(e.what()).find((d / kCheckpointFileName).string() + ": no checkpoint"), std::string::npos)
        << e.what();
  }
  // A packing is a state file, but not a checkpoint.
  const SceneDef scene = build_scene(bed(), "bed.json");
  World world(scene);
  write_packing((d / kCheckpointFileName).string(), world, json::object());
  try {
    read_checkpoint(d.string());
    FAIL();
  } catch (const StateFileError& e) {
    EXPECT_NE(std::string(e.what()).find("not a run checkpoint"), std::string::npos) << e.what();
  }
  // Cut short: the state file's checksum refuses it as a whole.
  write_checkpoint(d.string(), world, json::object());
  const std::string bytes = read_text(d / kCheckpointFileName);
  std::ofstream(d / kCheckpointFileName, std::ios::binary | std::ios::trunc) << bytes.substr(0, bytes.size() / 2);
  EXPECT_THROW(read_checkpoint(d.string()), StateFileError);
}

TEST(Checkpoint, CSVsShorterThanTheCheckpointSaysAreRefused) {
  const fs::path d = fresh_dir("ratchet_checkpoint");
  const SceneDef scene = build_scene(bed(), "bed.json");
  try {
    run_fresh(scene, d, [&](const World& w) {
      if (w.state().step == 300) request_stop(SIGINT);
    });
  } catch (const RunInterrupted&) {
  }
  clear_stop_request();
  fs::resize_file(d / "bodies.csv.partial", 10);
  try {
    resume(d);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bodies.csv.partial: cannot resume"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ratchet
