// Sweep plans: the grid's cartesian product (last key fastest, seeds innermost), a list
// of points, seeds versus realizations, the scene of each run, packings shared by the
// runs that differ only in what the packing key leaves out, rejected sweep files, and
// the completion test (same scene, same engine) for runs and packings, and why a
// checkpoint is not resumed.
#include "ratchet/run/sweep.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "ratchet/io/state_file.hpp"
#include "ratchet/run/checkpoint.hpp"
#include "ratchet/run/packing.hpp"
#include "ratchet/run/run_output.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using ::testing::HasSubstr;

const json kScene = json::parse(R"({
  "name": "s", "time": {"dt": 0.01},
  "container": {"type": "cone", "bottom_radius": 2.0},
  "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 0.5]}]},
  "thermal": {"start_time": 1.0, "heat_time": 0.5, "cycles": 1}
})");

struct Dir {
  fs::path path;
  explicit Dir(const std::string& name) : path(fs::temp_directory_path() / ("ratchet_sweep_" + name)) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~Dir() { fs::remove_all(path); }
  std::string write(const json& sweep) const {
    const fs::path p = path / "sweep.json";
    std::ofstream(p) << sweep.dump(2);
    return p.string();
  }
};

TEST(LoadSweep, GridTimesRealizationsInOdometerOrder) {
  Dir dir("grid");
  const json sweep = {{"scene", kScene},
                      {"grid", {{"thermal.alpha_p", {1e-4, 2e-4}}, {"solver.tolerance", {1e-3, 1e-4, 1e-5}}}},
                      {"realizations", 2}};
  const SweepPlan plan = load_sweep(dir.write(sweep), (dir.path / "out").string());
  EXPECT_EQ(plan.grid_keys, (std::vector<std::string>{"solver.tolerance", "thermal.alpha_p"}));  // sorted keys
  ASSERT_EQ(plan.runs.size(), 3u * 2u * 2u);
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    const SweepRun& r = plan.runs[i];
    EXPECT_EQ(r.id, static_cast<int>(i));
    EXPECT_EQ(r.seed, 1u + i % 2);  // seeds innermost
    ASSERT_EQ(r.params.size(), 2u);
    const double tol = r.params[0].second.get<double>(), alpha = r.params[1].second.get<double>();
    EXPECT_EQ(alpha, i / 2 % 2 == 0 ? 1e-4 : 2e-4);     // the last key turns fastest
    const std::vector<double> tolerances = {1e-3, 1e-4, 1e-5};
    EXPECT_EQ(tol, tolerances[i / 4]);
    EXPECT_EQ(r.scene.at("solver").at("tolerance"), tol);
    EXPECT_EQ(r.scene.at("thermal").at("alpha_p"), alpha);
    EXPECT_EQ(r.scene.at("seed"), r.seed);
  }
  EXPECT_EQ(run_dir(plan, 5), (dir.path / "out").string() + "/runs/5");
  EXPECT_EQ(packing_path(plan, "abc"), (dir.path / "out").string() + "/packings/abc.state");
}

// A list of points: the runs in the list's order, seeds innermost, one column per key.
TEST(LoadSweep, ListedPointsInTheirOrderTimesSeeds) {
  Dir dir("points");
  const json sweep = {{"scene", kScene},
                      {"points", {{{"thermal.alpha_p", 2e-4}, {"solver.tolerance", 1e-3}},
                                  {{"thermal.alpha_p", 1e-4}, {"solver.tolerance", 1e-5}}}},
                      {"seeds", {4, 2}}};
  const SweepPlan plan = load_sweep(dir.write(sweep), (dir.path / "out").string());
  EXPECT_EQ(plan.grid_keys, (std::vector<std::string>{"solver.tolerance", "thermal.alpha_p"}));
  ASSERT_EQ(plan.runs.size(), 4u);
  const std::vector<double> alpha = {2e-4, 2e-4, 1e-4, 1e-4}, tol = {1e-3, 1e-3, 1e-5, 1e-5};
  for (std::size_t i = 0; i < 4; ++i) {
    const SweepRun& r = plan.runs[i];
    EXPECT_EQ(r.seed, i % 2 == 0 ? 4u : 2u);
    EXPECT_EQ(r.scene.at("thermal").at("alpha_p"), alpha[i]);
    EXPECT_EQ(r.scene.at("solver").at("tolerance"), tol[i]);
    ASSERT_EQ(r.params.size(), 2u);
    EXPECT_EQ(r.params[1], (std::pair<std::string, json>{"thermal.alpha_p", alpha[i]}));
  }
  // A point the scene refuses names its run, before anything is written.
  const json bad = {{"scene", kScene}, {"points", {{{"time.dt", 0.01}}, {{"time.dt", -1.0}}}}};
  try {
    load_sweep(dir.write(bad), (dir.path / "out").string());
    FAIL() << "a negative time step was taken";
  } catch (const SceneError& e) {
    EXPECT_THAT(e.what(), HasSubstr("field 'time.dt'"));
    EXPECT_THAT(e.what(), HasSubstr("(in run 1 of sweep"));
  }
  EXPECT_FALSE(fs::exists(dir.path / "out"));
}

// alpha_p cannot act before the settle stage ends: one packing per (tolerance, seed).
TEST(LoadSweep, RunsShareThePackingTheirKeyAllows) {
  Dir dir("packings");
  const json sweep = {{"scene", kScene},
                      {"grid", {{"thermal.alpha_p", {1e-4, 2e-4}}, {"solver.tolerance", {1e-3, 1e-4}}}},
                      {"seeds", {7, 9}}};
  const SweepPlan plan = load_sweep(dir.write(sweep), dir.path.string());
  ASSERT_EQ(plan.runs.size(), 8u);
  EXPECT_EQ(plan.runs[0].seed, 7u);
  EXPECT_EQ(plan.runs[1].seed, 9u);
  ASSERT_EQ(plan.packings.size(), 4u);
  // Run ids 0..7: tolerance (slow), alpha_p, seed (fast); the packing of (tol, seed) is
  // shared by the two alpha_p values.
  EXPECT_EQ(plan.packings[0].runs, (std::vector<int>{0, 2}));
  EXPECT_EQ(plan.packings[1].runs, (std::vector<int>{1, 3}));
  EXPECT_EQ(plan.packings[2].runs, (std::vector<int>{4, 6}));
  EXPECT_EQ(plan.packings[3].runs, (std::vector<int>{5, 7}));
  for (const SweepPacking& p : plan.packings) EXPECT_FALSE(packing_ready(plan, p));
  EXPECT_EQ(needed_packings(plan), (std::vector<int>{0, 1, 2, 3}));
}

// `ratchet sweep --set`: the overrides change every run's scene after the file's `set`
// (the later wins), and a malformed one is refused naming it.
TEST(LoadSweep, CommandLineOverridesApplyToEveryRunAfterTheFilesSet) {
  Dir dir("overrides");
  const json sweep = {{"scene", kScene},
                      {"set", {{"solver.tolerance", 1e-3}, {"thermal.cycles", 2}}},
                      {"grid", {{"thermal.alpha_p", {1e-4, 2e-4}}}}};
  const SweepPlan plan =
      load_sweep(dir.write(sweep), dir.path.string(), {"solver.tolerance=1e-5", "solver.manifold_reuse=0.002"});
  ASSERT_EQ(plan.runs.size(), 2u);
  for (const SweepRun& r : plan.runs) {
    EXPECT_EQ(r.scene.at("solver").at("tolerance"), 1e-5);
    EXPECT_EQ(r.scene.at("solver").at("manifold_reuse"), 0.002);
    EXPECT_EQ(r.scene.at("thermal").at("cycles"), 2);
  }
  try {
    load_sweep(dir.write(sweep), dir.path.string(), {"solver.tolerance"});
    FAIL() << "an override without '=' was taken";
  } catch (const SceneError& e) {
    EXPECT_THAT(e.what(), HasSubstr("--set solver.tolerance"));
  }
}

TEST(LoadSweep, RejectsBadSweepsBeforeWritingAnything) {
  Dir dir("bad");
  const std::string out = (dir.path / "out").string();
  auto message = [&](const json& sweep) {
    try {
      load_sweep(dir.write(sweep), out);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(message({{"scene", kScene}, {"grids", json::object()}}), HasSubstr("'grids': unknown field"));
  EXPECT_THAT(message({{"scene", kScene}, {"grid", {{"time.dt", {0.01}}}}, {"points", {{{"time.dt", 0.01}}}}}),
              HasSubstr("sweep.json: field 'points': expected either a grid or a list of points, not both"));
  EXPECT_THAT(message({{"grid", json::object()}}), HasSubstr("'scene'"));
  EXPECT_THAT(message({{"scene", kScene}, {"grid", {{"time.dt", json::array()}}}}), HasSubstr("grid.time.dt"));
  EXPECT_THAT(message({{"scene", kScene}, {"realizations", 0}}), HasSubstr("realizations"));
  EXPECT_THAT(message({{"scene", kScene}, {"seeds", {1, -2}}}), HasSubstr("seeds"));
  // A bad value in the second grid point names its run.
  EXPECT_THAT(message({{"scene", kScene}, {"grid", {{"time.dt", {0.01, -1.0}}}}}), HasSubstr("(in run 1 of sweep"));
  EXPECT_FALSE(fs::exists(out));
}

TEST(SummaryCsvCell, EveryKindOfGridValueKeepsItsColumn) {
  EXPECT_EQ(summary_csv_cell(json(6)), "6");
  EXPECT_EQ(summary_csv_cell(json(0.001)), "0.001");
  EXPECT_EQ(summary_csv_cell(json(true)), "true");   // a boolean grid (e.g. container.floor_expands)
  EXPECT_EQ(summary_csv_cell(json(false)), "false");
  EXPECT_EQ(summary_csv_cell(json(nullptr)), "");
  EXPECT_EQ(summary_csv_cell(json("spring")), "spring");
  EXPECT_EQ(summary_csv_cell(json("a, \"b\"")), "\"a, \"\"b\"\"\"");
  EXPECT_EQ(summary_csv_cell(json::array({0, 3})), "\"[0,3]\"");
}

TEST(RunCompleted, OnlyACompletedRunJsonOfTheSameSceneAndEngine) {
  Dir dir("completed");
  const SweepPlan plan = load_sweep(dir.write({{"scene", kScene}, {"realizations", 1}}), dir.path.string());
  ASSERT_EQ(plan.runs.size(), 1u);
  const SweepRun& run = plan.runs[0];
  EXPECT_FALSE(run_completed(plan, run));
  fs::create_directories(run_dir(plan, 0));
  auto write = [&](const json& j) { std::ofstream(run_dir(plan, 0) + "/run.json") << j.dump(); };
  const std::string hash = fnv1a_hex(run.scene.dump());
  write({{"status", "completed"}, {"scene_hash", hash}, {"engine", engine_record()}});
  EXPECT_TRUE(run_completed(plan, run));
  write({{"status", "completed"}, {"scene_hash", "0000000000000000"}, {"engine", engine_record()}});  // another scene
  EXPECT_FALSE(run_completed(plan, run));
  write({{"status", "running"}, {"scene_hash", hash}, {"engine", engine_record()}});
  EXPECT_FALSE(run_completed(plan, run));
  // Another engine: the same version built from other sources, or a run.json from
  // before the engine was recorded. Its run is run again.
  json other = engine_record();
  other["source_hash"] = "0123456789abcdef";
  write({{"status", "completed"}, {"scene_hash", hash}, {"engine", other}});
  EXPECT_FALSE(run_completed(plan, run));
  write({{"status", "completed"}, {"scene_hash", hash}});
  EXPECT_FALSE(run_completed(plan, run));
  other = engine_record();
  other["version"] = "0.0.1";
  write({{"status", "completed"}, {"scene_hash", hash}, {"engine", other}});
  EXPECT_FALSE(run_completed(plan, run));
  // The commit is provenance, not identity: a commit that left the engine alone keeps the run.
  other = engine_record();
  other["commit"] = "0000000000000000000000000000000000000000";
  write({{"status", "completed"}, {"scene_hash", hash}, {"engine", other}});
  EXPECT_TRUE(run_completed(plan, run));
}

// A packing made by another engine is made again, never reused.
TEST(PackingReady, OnlyAWholePackingOfTheSameKeyAndEngine) {
  Dir dir("packing_engine");
  const SweepPlan plan = load_sweep(dir.write({{"scene", kScene}}), dir.path.string());
  ASSERT_EQ(plan.packings.size(), 1u);
  const SweepPacking& p = plan.packings[0];
  EXPECT_FALSE(packing_ready(plan, p));  // missing
  World world(build_scene(plan.runs[0].scene, "s.json"));
  fs::create_directories(dir.path / "packings");
  write_packing(packing_path(plan, p.key), world, json::object());
  EXPECT_TRUE(packing_ready(plan, p));
  StateFile f = read_state_file(packing_path(plan, p.key));
  EXPECT_EQ(f.meta.at("engine"), engine_record());
  f.meta["engine"]["source_hash"] = "0123456789abcdef";
  write_state_file(packing_path(plan, p.key), f);
  EXPECT_FALSE(packing_ready(plan, p));
  EXPECT_EQ(needed_packings(plan), (std::vector<int>{0}));
}

// A run that cannot go on from the checkpoint it left starts over: the sweep says why
// (the steps it held are lost), and a missing checkpoint is no reason.
TEST(ResumableCheckpoint, SaysWhyACheckpointOfAnotherEngineOrSceneIsNotResumed) {
  Dir dir("resumable");
  const SweepPlan plan = load_sweep(dir.write({{"scene", kScene}}), dir.path.string());
  const std::string d = run_dir(plan, 0);
  fs::create_directories(d);
  World world(build_scene(plan.runs[0].scene, "s.json"));
  std::string why = "stale";
  EXPECT_FALSE(resumable_checkpoint(d, world.scene(), &why).has_value());
  EXPECT_EQ(why, "");  // none: nothing lost

  write_checkpoint(d, world, json::object());
  EXPECT_TRUE(resumable_checkpoint(d, world.scene(), &why).has_value());
  EXPECT_EQ(why, "");

  json other_scene = plan.runs[0].scene;
  other_scene["time"]["dt"] = 0.02;
  World other(build_scene(other_scene, "s.json"));
  write_checkpoint(d, other, json::object());
  EXPECT_FALSE(resumable_checkpoint(d, world.scene(), &why).has_value());
  EXPECT_THAT(why, HasSubstr("a checkpoint of another scene"));

  write_checkpoint(d, world, json::object());
  const std::string path = d + "/" + kCheckpointFileName;
  StateFile f = read_state_file(path);
  f.meta["engine"]["source_hash"] = "0123456789abcdef";
  write_state_file(path, f);
  EXPECT_FALSE(resumable_checkpoint(d, world.scene(), &why).has_value());
  EXPECT_THAT(why, HasSubstr(path));
  EXPECT_THAT(why, HasSubstr("only the same engine continues a run bit for bit"));
}

}  // namespace
}  // namespace ratchet
