// Settled packings: the key, the settle stage (ended by the KE threshold of a settle
// section, or at thermal.start_time without one), refusal of a packing of another
// scene, and the restart contract: a run from a packing writes the same rows, bit for
// bit, as the run from t = 0 after the packing's step, also when the packing was made
// with another thermal protocol (which the key leaves out).
#include "ratchet/run/packing.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ratchet/io/state_file.hpp"
#include "ratchet/observe/energy.hpp"
#include "ratchet/run/runner.hpp"

namespace ratchet {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using ::testing::HasSubstr;

// Small and short: 14 polyhedra poured into a 4-degree cone, settled to t = 3, one
// cycle. At dt 0.005 the settle stage ends a few ulps below start_time (step 600).
// (No settle section: settled() adds one.)
json bed() {
  return json::parse(R"({
    "name": "pack", "seed": 5, "time": {"dt": 0.005},
    "solver": {"tolerance": 1e-4, "max_iterations": 100},
    "container": {"type": "cone", "bottom_radius": 2.5, "opening_angle_deg": 4.0},
    "particles": {"generate": {"count": 14, "shape": "polyhedron", "vertices": 10, "radius_range": [0.3, 0.5]}},
    "thermal": {"start_time": 3.0, "heat_time": 0.5, "hold_time": 0.25, "cool_time": 0.5, "cycles": 1,
                "alpha_p": 1e-3, "alpha_c": 1e-2},
    "outputs": {"timeseries_every": 1, "bodies_every": 10, "volume": true, "segment_forces": true,
                "steady_cycles": [0, 0], "pressure_window": 0.1,
                "displacement": {"cell": 1.0, "windows": [[0, 1]]}, "wall_profile_bins": 3}
  })");
}

json with(json j, const std::string& path, const json& value) {
  apply_override(j, path + "=" + value.dump(), "test");
  return j;
}

// The same bed with a settle section: settled when KE <= 1e-4 x its peak (t = 6.75
// for this bed), then a rest of 0.25 before the cycle.
json settled() {
  json j = bed();
  j["settle"] = {{"ke_ratio", 1e-4}, {"max_time", 10.0}};
  j["thermal"]["start_time"] = 0.25;
  return j;
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("ratchet_packing_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::vector<std::string> lines_of(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

json read_json(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

std::vector<std::string> split(const std::string& row) {
  std::vector<std::string> out;
  std::stringstream ss(row);
  for (std::string c; std::getline(ss, c, ',');) out.push_back(c);
  return out;
}

// Rows after `step` (first column), without the wall-clock columns time_*.
std::vector<std::string> rows_after(const fs::path& csv, long long step) {
  const auto lines = lines_of(csv);
  const auto header = split(lines.at(0));
  std::vector<std::string> out;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto cells = split(lines[i]);
    if (std::stoll(cells.at(0)) <= step) continue;
    std::string kept;
    for (std::size_t c = 0; c < cells.size(); ++c)
      if (header.at(c).rfind("time_", 0) != 0) kept += cells[c] + ",";
    out.push_back(kept);
  }
  return out;
}

std::string packing_of(const json& scene, const fs::path& file) {
  World w(build_scene(scene, "packer.json"));
  const json settle = settle_world(w);
  write_packing(file.string(), w, settle);
  return packing_key(w.scene());
}

TEST(Packing, KeyLeavesOutOnlyWhatCannotActBeforeTheSettleStageEnds) {
  const std::vector<std::pair<std::string, json>> same{
      {"thermal.alpha_c", 1e-4}, {"thermal.alpha_p", 2e-4}, {"thermal.T1", 50},   {"thermal.heat_time", 2.0},
      {"thermal.hold_time", 0.0}, {"thermal.cool_time", 3.0}, {"thermal.cycles", 4}, {"name", "other"},
      {"description", "text"},    {"time.duration", 100.0},  {"solver.threads", 2},
      {"outputs", json{{"timeseries_every", 7}}}, {"container.floor_expands", false}};
  const std::vector<std::pair<std::string, json>> different{
      {"container.opening_angle_deg", 6.0}, {"seed", 6}, {"thermal.T0", 10.0}, {"time.dt", 0.004},
      {"materials.friction", 0.3}, {"solver.p_gap", 0.2}, {"solver.criterion", "velocity"},
      {"effects.container_expansion", false}, {"particles.generate.count", 13}};
  for (const json& base : {bed(), settled()}) {
    const std::string k = packing_key(build_scene(base, "a.json"));
    EXPECT_EQ(k.size(), 16u);
    for (const auto& [path, value] : same) EXPECT_EQ(packing_key(build_scene(with(base, path, value), "b.json")), k) << path;
    for (const auto& [path, value] : different)
      EXPECT_NE(packing_key(build_scene(with(base, path, value), "b.json")), k) << path;
    json no_seed = with(base, "seed", 1);
    const std::string k1 = packing_key(build_scene(no_seed, "c.json"));
    no_seed.erase("seed");
    EXPECT_EQ(packing_key(build_scene(no_seed, "c.json")), k1);  // the default seed, as a sweep writes it
  }
  // Without a settle section the stage ends at start_time; with one, start_time is the
  // rest after the stage and cannot act in it, while the threshold and the time allowed can.
  EXPECT_NE(packing_key(build_scene(with(bed(), "thermal.start_time", 2.5), "b.json")), packing_key(build_scene(bed(), "a")));
  const std::string ks = packing_key(build_scene(settled(), "a.json"));
  EXPECT_EQ(packing_key(build_scene(with(settled(), "thermal.start_time", 2.5), "b.json")), ks);
  EXPECT_NE(packing_key(build_scene(with(settled(), "settle.ke_ratio", 1e-3), "b.json")), ks);
  EXPECT_NE(packing_key(build_scene(with(settled(), "settle.max_time", 4.0), "b.json")), ks);
  EXPECT_NE(ks, packing_key(build_scene(bed(), "a")));
}

// The key test: pack with one thermal protocol, run another from the packing, and
// compare with that other protocol's run from t = 0. Without a settle section the
// packing ends at start_time; with one, where the KE threshold is met.
void expect_restart_is_bit_identical(const json& base, const std::string& name) {
  const fs::path d = scratch("restart_" + name);
  const json other = with(with(with(base, "thermal.alpha_c", 2.5e-3), "thermal.T1", 80), "thermal.heat_time", 0.75);
  ASSERT_EQ(packing_key(build_scene(base, "a")), packing_key(build_scene(other, "b")));
  {
    World w(build_scene(other, "straight.json"));
    RunOptions opt;
    opt.out_dir = (d / "straight").string();
    (void)run_world(w, opt);
  }
  const std::string key = packing_of(base, d / "p.state");
  World w(build_scene(other, "restart.json"));
  const json meta = load_packing((d / "p.state").string(), w);
  const long long k = w.state().step;
  RunOptions opt;
  opt.out_dir = (d / "restart").string();
  opt.packing = packing_reference((d / "p.state").string(), w);
  opt.packing_settle = meta.at("settle");
  (void)run_world(w, opt);

  for (const char* f : {"timeseries.csv", "bodies.csv"}) {
    const auto a = rows_after(d / "straight" / f, k), b = rows_after(d / "restart" / f, k);
    ASSERT_GT(a.size(), 10u) << f;
    EXPECT_EQ(a, b) << f;
  }
  // The first row of the run from the packing is the packing's state (step k).
  EXPECT_EQ(split(lines_of(d / "restart" / "bodies.csv").at(1)).at(0), std::to_string(k));
  for (const char* f : {"cycles.csv", "wall_profile.csv", "displacement_0_1.csv"})
    EXPECT_EQ(lines_of(d / "straight" / f), lines_of(d / "restart" / f)) << f;
  const json a = read_json(d / "straight" / "run.json"), b = read_json(d / "restart" / "run.json");
  // The observables agree; the solver counts cover each run's own steps (the straight
  // run's include the pour's), so they are compared apart.
  json sa = a.at("summary"), sb = b.at("summary");
  EXPECT_LE(sb.at("unconverged_steps").get<long long>(), sa.at("unconverged_steps").get<long long>());
  for (const char* key : {"unconverged_steps", "unconverged_fraction"}) {
    sa.erase(key);
    sb.erase(key);
  }
  EXPECT_EQ(sa, sb);
  EXPECT_TRUE(a.at("summary").at("P_max").is_number());
  EXPECT_EQ(a.at("settle"), b.at("settle"));  // recorded by the run, and copied from the packing
  EXPECT_EQ(a.at("settle").at("step_end"), k);
  EXPECT_EQ(a.at("steps"), b.at("steps"));
  EXPECT_TRUE(a.at("packing").is_null());
  EXPECT_EQ(b.at("packing").at("key"), key);
  EXPECT_EQ(b.at("packing").at("step"), k);
  fs::remove_all(d);
}

TEST(Packing, RunFromPackingIsBitIdenticalAfterThePackingStep) {
  expect_restart_is_bit_identical(bed(), "fixed");
  // Without a settle section: the last step with t <= start_time.
  World w(build_scene(bed(), "a.json"));
  (void)settle_world(w);
  EXPECT_EQ(w.state().step, 600);
  EXPECT_LE(w.state().t, 3.0);
  EXPECT_GT(w.state().t + 0.005, 3.0);
}

TEST(Packing, RunFromSettledPackingIsBitIdenticalAfterThePackingStep) {
  expect_restart_is_bit_identical(settled(), "settled");
}

TEST(Packing, PackingOfAnotherSceneIsRefusedBeforeAnythingChanges) {
  const fs::path d = scratch("refused");
  const std::string file = (d / "p.state").string();
  (void)packing_of(bed(), file);
  World w(build_scene(with(bed(), "container.opening_angle_deg", 0.0), "flat.json"));
  const State before = w.state();
  try {
    (void)load_packing(file, w);
    FAIL() << "a packing of a 4-degree cone was accepted for a 0-degree one";
  } catch (const StateFileError& e) {
    EXPECT_THAT(e.what(), HasSubstr(file + ": packing of a different scene"));
    EXPECT_THAT(e.what(), HasSubstr("flat.json"));
    EXPECT_THAT(e.what(), HasSubstr("field 'container.opening_angle_deg' is 4.0 in the packing's scene and 0.0 in this one"));
  }
  EXPECT_EQ(w.state().step, before.step);
  EXPECT_EQ(w.state().x, before.x);
  World fewer(build_scene(with(bed(), "particles.generate.count", 12), "fewer.json"));
  try {
    (void)load_packing(file, fewer);
    FAIL();
  } catch (const StateFileError& e) {
    EXPECT_THAT(e.what(), HasSubstr(file + ": packing of 14 bodies, but fewer.json has 12"));
  }
  // A half-written packing is refused whole.
  const std::string cut = (d / "cut.state").string();
  std::string bytes;
  {
    std::ifstream in(file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  World same(build_scene(bed(), "same.json"));
  EXPECT_THROW((void)load_packing(cut, same), StateFileError);
  EXPECT_EQ(same.state().step, 0);
  // A run that ends before the packing does cannot start from it.
  World shorter(build_scene(with(bed(), "time.duration", 2.0), "short.json"));
  try {
    (void)load_packing(file, shorter);
    FAIL();
  } catch (const StateFileError& e) {
    EXPECT_THAT(e.what(), HasSubstr("after the last step (400) of short.json"));
  }
  fs::remove_all(d);
}

// A packing fixes the bed; how closely a run from it is solved, the contact compliance
// and the gap relaxation may differ (the study of what accuracy costs varies tolerance,
// criterion, cap, acceleration, compliance and p_gap from one bed), and with a settle
// section the time step too. Anything else that shapes the bed is still refused.
TEST(Packing, SolveKnobsMayDifferFromThePackingsScene) {
  const fs::path d = scratch("knobs");
  const std::string file = (d / "p.state").string();
  (void)packing_of(bed(), file);
  json knobs = with(with(with(bed(), "solver.tolerance", 1e-7), "solver.max_iterations", 5000), "solver.criterion",
                    "velocity");
  knobs = with(with(knobs, "solver.acceleration", "anderson"), "solver.anderson_depth", 3);
  knobs = with(with(with(knobs, "solver.compliance", 0.03), "solver.p_gap", 0.3), "solver.method", "nsgs");
  World w(build_scene(knobs, "knobs.json"));
  EXPECT_NE(packing_key(w.scene()), packing_key(build_scene(bed(), "a.json")));
  EXPECT_NO_THROW((void)load_packing(file, w));
  EXPECT_GT(w.state().step, 0);
  World other(build_scene(with(with(bed(), "solver.tolerance", 1e-7), "materials.friction", 0.3), "mu.json"));
  try {
    (void)load_packing(file, other);
    FAIL() << "a packing made with the default friction was accepted for 0.3";
  } catch (const StateFileError& e) {
    EXPECT_THAT(e.what(), HasSubstr("field 'materials' is absent in the packing's scene and {\"friction\":0.3}"));
  }
  // Without a settle section the packing's step counts in its own h: another h is refused.
  World finer(build_scene(with(bed(), "time.dt", 0.0025), "finer.json"));
  try {
    (void)load_packing(file, finer);
    FAIL() << "a packing of a scene without settle section was accepted for another time step";
  } catch (const StateFileError& e) {
    EXPECT_THAT(e.what(), HasSubstr("field 'time.dt'"));
  }
  fs::remove_all(d);
}

// With a settle section a run from the packing may take another h: it counts its steps
// from the packing's state at its own h, and its protocol from the packing's time.
TEST(Packing, WithASettleSectionTheTimeStepMayDiffer) {
  const fs::path d = scratch("dt");
  const std::string file = (d / "p.state").string();
  (void)packing_of(settled(), file);
  const StateFile f = read_state_file(file);
  const double h = build_scene(settled(), "a.json").dt;
  World finer(build_scene(with(settled(), "time.dt", h / 2), "finer.json"));
  ASSERT_NO_THROW((void)load_packing(file, finer));
  EXPECT_EQ(finer.state().t, f.state.t);
  const SceneDef& s = finer.scene();
  EXPECT_EQ(s.steps - f.state.step, static_cast<std::int64_t>(std::llround(s.settle.run_time / (h / 2))));
  EXPECT_EQ(s.thermal.start_time, f.state.t + s.settle.rest_time);
  const RunResult r = run_world(finer, {});
  EXPECT_NEAR(finer.state().t, f.state.t + s.settle.run_time, 1e-9);
  EXPECT_TRUE(r.summary.is_object());
  fs::remove_all(d);
}

// The settle stage of a settle section ends at the first state with KE <= ke_ratio x
// the peak so far, and the protocol then counts from there.
TEST(Packing, SettleStageEndsAtTheFirstStateBelowTheThreshold) {
  const SceneDef scene = build_scene(settled(), "a.json");
  World w(scene);
  EXPECT_TRUE(w.settling());
  const json r = settle_world(w);
  EXPECT_FALSE(w.settling());
  const long long k = w.state().step;
  EXPECT_EQ(r.at("step_end"), k);
  EXPECT_EQ(r.at("t_end"), w.state().t);
  EXPECT_EQ(r.at("reached"), true);
  EXPECT_EQ(r.at("t_settled"), w.state().t);
  EXPECT_EQ(r.at("ke_ratio_threshold"), 1e-4);
  EXPECT_LE(r.at("ke_ratio").get<double>(), 1e-4);
  EXPECT_EQ(r.at("ke_ratio").get<double>(), r.at("ke_end").get<double>() / r.at("ke_peak").get<double>());
  EXPECT_GT(w.state().t, 2.5);  // the bed is still moving well after the pour
  EXPECT_LT(w.state().t, 10.0);
  // No earlier state met the threshold: replay the pour.
  World replay(scene);
  double peak = 0.0;
  for (long long i = 1; i < k; ++i) {
    replay.step();
    const double ke = kinetic_energy(replay.scene(), replay.state());
    peak = std::max(peak, ke);
    ASSERT_GT(ke, 1e-4 * peak) << "step " << i;
  }
  // The protocol now starts after the rest (0.25) and the run ends one run time later.
  EXPECT_EQ(w.scene().thermal.start_time, w.state().t + 0.25);
  EXPECT_EQ(w.scene().steps, k + std::llround(scene.settle.run_time / 0.005));
  EXPECT_EQ(w.state().T, 0.0);  // still T0
  // The threshold changes where the stage ends, not the pour before it.
  World coarse(build_scene(with(settled(), "settle.ke_ratio", 1e-2), "b.json"));
  const json rc = settle_world(coarse);
  EXPECT_LT(rc.at("step_end").get<long long>(), k);
  EXPECT_EQ(rc.at("ke_peak"), r.at("ke_peak"));
}

TEST(Packing, UnsettledBedFailsAtMaxTimeNamingTheFields) {
  World strict(build_scene(with(with(settled(), "settle.ke_ratio", 1e-300), "settle.max_time", 0.5), "strict.json"));
  try {
    (void)settle_world(strict);
    FAIL() << "a threshold of 1e-300 was reached";
  } catch (const SettleError& e) {
    EXPECT_THAT(e.what(), HasSubstr("strict.json: the bed did not settle by settle.max_time = 0.5"));
    EXPECT_THAT(e.what(), HasSubstr("is above settle.ke_ratio = 1e-300"));
  }
  EXPECT_NEAR(strict.state().t, 0.5, 1e-9);
  EXPECT_TRUE(strict.settling());
  // run_world stops the same way and leaves no run.json (docs/output-format.md).
  const fs::path d = scratch("unsettled");
  World w(build_scene(with(with(settled(), "settle.ke_ratio", 1e-300), "settle.max_time", 0.5), "strict.json"));
  RunOptions opt;
  opt.out_dir = (d / "out").string();
  EXPECT_THROW((void)run_world(w, opt), SettleError);
  EXPECT_FALSE(fs::exists(d / "out" / "run.json"));
  fs::remove_all(d);
}

TEST(Packing, WithoutSettleSectionTheStageEndsAtStartTime) {
  World plain(build_scene(bed(), "c.json"));
  EXPECT_FALSE(plain.settling());
  const json n = settle_world(plain);
  EXPECT_TRUE(n.at("reached").is_null());
  EXPECT_TRUE(n.at("ke_ratio_threshold").is_null());
  EXPECT_TRUE(n.at("t_settled").is_null());
  EXPECT_EQ(n.at("step_end"), 600);
  EXPECT_GT(n.at("ke_ratio").get<double>(), 0.0);
  EXPECT_THROW(plain.end_settle_stage(), std::logic_error);
}

// A packing says whether its bed reached the threshold; one that did not, or was made
// for a larger max_time, is refused.
TEST(Packing, SettledSceneRefusesPackingsThatDidNotSettle) {
  const fs::path d = scratch("unsettled_packing");
  World w(build_scene(settled(), "a.json"));
  json r = settle_world(w);
  r["reached"] = false;
  write_packing((d / "p.state").string(), w, r);
  World fresh(build_scene(settled(), "a.json"));
  try {
    (void)load_packing((d / "p.state").string(), fresh);
    FAIL();
  } catch (const StateFileError& e) {
    EXPECT_THAT(e.what(), HasSubstr("does not say that the bed reached settle.ke_ratio"));
  }
  EXPECT_TRUE(fresh.settling());
  EXPECT_EQ(fresh.state().step, 0);
  fs::remove_all(d);
}

TEST(Packing, SceneWithoutThermalSectionHasNoSettleStage) {
  json j = bed();
  j.erase("thermal");
  j["time"]["duration"] = 0.1;
  World w(build_scene(j, "cold.json"));
  EXPECT_FALSE(has_settle_stage(w.scene()));
  EXPECT_THROW((void)settle_world(w), std::invalid_argument);
  EXPECT_THROW((void)load_packing("/nonexistent.state", w), StateFileError);
}

}  // namespace
}  // namespace ratchet
