// A 2-cycle run of a small bed through the whole chain (pour, settle, cycle, every
// observable), and the stage bookkeeping with a zero-length hold.
#include "ratchet/run/observers.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ratchet/observe/wall_pressure.hpp"
#include "ratchet/run/runner.hpp"

namespace ratchet {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json small_bed() {
  return json::parse(R"({
    "name": "chain", "seed": 3, "time": {"dt": 0.004},
    "solver": {"tolerance": 1e-4, "max_iterations": 200},
    "container": {"type": "cone", "bottom_radius": 3.0, "opening_angle_deg": 4.0},
    "particles": {"generate": {"count": 40, "shape": "polyhedron", "vertices": 12, "radius_range": [0.3, 0.5]}},
    "thermal": {"start_time": 4.0, "heat_time": 1.0, "hold_time": 0.5, "cool_time": 1.0, "cycles": 2},
    "outputs": {"timeseries_every": 50, "volume": true, "segment_forces": true, "steady_cycles": [1, 1],
                "pressure_window": 0.2, "displacement": {"cell": 1.0, "windows": [[0, 1], [0, 2]]},
                "wall_profile_bins": 4, "vtk_cycles": [1]}
  })");
}

std::vector<std::string> lines_of(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("ratchet_observers_" + name);
  fs::remove_all(d);
  return d;
}

TEST(RunObservers, TwoCycleChainWritesEveryObservable) {
  const fs::path d = scratch("chain");
  World world(build_scene(small_bed(), "chain.json"));
  RunOptions opt;
  opt.out_dir = d.string();
  const RunResult r = run_world(world, opt);
  // cycles.csv: one row per cycle with a positive peak inside its cycle.
  const auto cycles = lines_of(d / "cycles.csv");
  ASSERT_EQ(cycles.size(), 3u);
  for (int k = 0; k < 2; ++k) {
    std::stringstream row(cycles[static_cast<std::size_t>(k + 1)]);
    std::string cell;
    std::vector<double> v;
    while (std::getline(row, cell, ',')) v.push_back(std::stod(cell));
    EXPECT_EQ(v[0], k);
    EXPECT_GT(v[1], 0.0);                              // peak pressure
    EXPECT_GE(v[2], 4.0 + 3.0 * k);                    // t_peak inside cycle k (cycle time 3)
    EXPECT_LE(v[2], 4.0 + 3.0 * (k + 1) + 1e-9);
    EXPECT_GT(v[3], 0.5);                              // V/V0 at the ends of heating and cooling
    EXPECT_LT(v[3], 1.5);
  }
  // Summary: P_max is the peak of cycle 1 (steady window [1, 1]).
  ASSERT_TRUE(r.summary.contains("P_max"));
  EXPECT_GT(r.summary["P_max"].get<double>(), 0.0);
  EXPECT_TRUE(r.summary.contains("V_over_V0_end"));
  EXPECT_TRUE(r.summary.contains("W_rms_0_1"));
  EXPECT_TRUE(r.summary.contains("W_rms_0_2"));
  // Timeseries: the asked-for columns.
  const auto ts = lines_of(d / "timeseries.csv");
  EXPECT_NE(ts[0].find(",V_over_V0"), std::string::npos);
  EXPECT_NE(ts[0].find(",wall_force_seg_15"), std::string::npos);
  // Fields, profile and VTK at the ends of heating and cooling of cycle 1.
  EXPECT_GT(lines_of(d / "displacement_0_1.csv").size(), 1u);
  EXPECT_GT(lines_of(d / "displacement_0_2.csv").size(), 1u);
  EXPECT_EQ(lines_of(d / "wall_profile.csv").size(), 1u + 2u * 4u);  // header + 2 cycles x 4 bins
  for (const char* f : {"particles_cycle1_end_heating.vtp", "contacts_cycle1_end_cooling.vtp",
                        "container_cycle1_end_cooling.vtp", "particles.pvd"})
    EXPECT_TRUE(fs::exists(d / "vtk" / f)) << f;
  EXPECT_FALSE(fs::exists(d / "vtk" / "particles_cycle0_end_heating.vtp"));  // only the cycles asked for
  fs::remove_all(d);
}

std::vector<double> cells_of(const std::string& row) {
  std::stringstream ss(row);
  std::vector<double> v;
  for (std::string c; std::getline(ss, c, ',');) v.push_back(std::stod(c));
  return v;
}

// outputs.settled_profile_time: the settled bed's profile (cycle -1), averaged over the
// last 1.0 before cycling. Its band stresses times the band areas add up to the side
// force of timeseries.csv averaged over the same steps (every contact point counts in
// some band), and it comes before the cold-hold rows.
TEST(RunObservers, SettledProfileAveragesTheWindowBeforeCycling) {
  json j = small_bed();
  j["outputs"]["settled_profile_time"] = 1.0;
  j["outputs"]["timeseries_every"] = 1;
  const fs::path d = scratch("settled_profile");
  const SceneDef scene = build_scene(j, "settled.json");
  World world(scene);
  RunOptions opt;
  opt.out_dir = d.string();
  run_world(world, opt);
  const auto prof = lines_of(d / "wall_profile.csv");
  ASSERT_EQ(prof.size(), 1u + 3u * 4u);  // header + settled + 2 cycles, 4 bins each
  const double H = cells_of(prof[4]).at(4);
  double total = 0.0;
  for (int k = 0; k < 4; ++k) {
    const std::vector<double> v = cells_of(prof[static_cast<std::size_t>(k + 1)]);
    EXPECT_EQ(v[0], -1.0);
    EXPECT_NEAR(v[1], 4.0, 1e-9);  // written where cycling starts
    EXPECT_EQ(v[2], k);
    EXPECT_GE(v[5], 0.0);
    // 1 / area of band k: the stress of a unit force in the middle of the band.
    const ContainerDef& c = scene.container;
    const double inv_area = wall_stress_profile({H * (k + 0.5) / 4}, {1.0}, c.bottom_radius, c.opening_angle_deg,
                                                c.segments, H, 4)[static_cast<std::size_t>(k)];
    total += v[5] / inv_area;
  }
  EXPECT_EQ(cells_of(prof[5]).at(0), 0.0);  // then cycle 0
  // timeseries: wall_force_side (column 9) over the steps of the window (t in (3, 4]:
  // steps 751 to 1000).
  const auto ts = lines_of(d / "timeseries.csv");
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 1; i < ts.size(); ++i) {
    const std::vector<double> v = cells_of(ts[i]);
    if (v[0] > 750 && v[0] <= 1000) { sum += v[9]; ++n; }
  }
  EXPECT_EQ(n, 250);  // 1.0 / h
  EXPECT_GT(sum, 0.0);
  EXPECT_NEAR(total, sum / n, 1e-9 * sum / n);  // round-off of the binning only
  fs::remove_all(d);
}

// t is accumulated (t += h): after 12,250 steps of h = 0.004 the last state lies
// 1.35e-9 h before the end of the last cycle (start 1 + 6 x 8). It still ends that
// cycle: the last snapshot is taken, so the window [3, 6] gets its field, and the last
// cold hold its profile row.
TEST(RunObservers, LastCycleEndsDespiteRoundOffInTheAccumulatedTime) {
  const json j = json::parse(R"({
    "name": "long", "time": {"dt": 0.004},
    "container": {"type": "cone", "bottom_radius": 2.0},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 0.5]}]},
    "thermal": {"start_time": 1.0, "heat_time": 3.0, "hold_time": 1.0, "cool_time": 3.0, "cycles": 6},
    "outputs": {"timeseries_every": 1000, "displacement": {"cell": 1.0, "windows": [[0, 3], [3, 6]]},
                "wall_profile_bins": 1}
  })");
  const fs::path d = scratch("round_off");
  World world(build_scene(j, "long.json"));
  ASSERT_EQ(world.scene().steps, 12250);
  RunOptions opt;
  opt.out_dir = d.string();
  run_world(world, opt);
  EXPECT_LT(world.state().t - 1.0, 48.0);  // the round-off this test is about
  EXPECT_TRUE(fs::exists(d / "displacement_0_3.csv"));
  EXPECT_TRUE(fs::exists(d / "displacement_3_6.csv"));
  EXPECT_EQ(lines_of(d / "cycles.csv").size(), 1u + 6u);
  EXPECT_EQ(lines_of(d / "wall_profile.csv").size(), 1u + 6u);  // one band per cold hold
  fs::remove_all(d);
}

TEST(RunObservers, ZeroLengthHoldStillEndsEachCycle) {
  json j = small_bed();
  j["thermal"]["hold_time"] = 0.0;
  j["particles"]["generate"]["count"] = 6;
  const fs::path d = scratch("zero_hold");
  World world(build_scene(j, "zero_hold.json"));
  RunOptions opt;
  opt.out_dir = d.string();
  run_world(world, opt);
  EXPECT_TRUE(fs::exists(d / "displacement_0_2.csv"));  // needs the snapshot at the end of cycle 1
  EXPECT_EQ(lines_of(d / "wall_profile.csv").size(), 1u + 2u * 4u);
  fs::remove_all(d);
}

TEST(RunObservers, NothingAskedNothingComputed) {
  json j = small_bed();
  j["outputs"] = {{"timeseries_every", 50}, {"cycles", false}};
  j["time"]["duration"] = 1.0;  // ends before cycling starts
  j["particles"]["generate"]["count"] = 6;
  const fs::path d = scratch("nothing");
  World world(build_scene(j, "nothing.json"));
  RunOptions opt;
  opt.out_dir = d.string();
  const RunResult r = run_world(world, opt);
  EXPECT_FALSE(r.summary.contains("V_over_V0_end"));
  EXPECT_TRUE(r.summary["P_max"].is_null());  // no cycle reached
  EXPECT_FALSE(fs::exists(d / "cycles.csv"));
  EXPECT_FALSE(fs::exists(d / "vtk"));
  EXPECT_EQ(lines_of(d / "timeseries.csv")[0].find("V_over_V0"), std::string::npos);
  fs::remove_all(d);
}

// At dt 0.005 step 800 ends at t = 4 - 6e-14: within round-off of start_time 4, so the
// start of cycling (V0, snapshot 0) is taken there, and must not be taken again at step
// 801, which also lies past the mark.
TEST(RunObservers, StartOfCyclingIsTakenOnceWhenTheMarkFallsJustBelowAStep) {
  const json j = json::parse(R"({
    "name": "mark", "time": {"dt": 0.005},
    "container": {"type": "planes", "planes": [{"normal": [0, 0, 1], "point": [0, 0, 0]}]},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 0.5]}]},
    "thermal": {"start_time": 4.0, "heat_time": 1.0, "cycles": 1, "alpha_p": 1e-2, "alpha_c": 0},
    "outputs": {"volume": true}
  })");
  const fs::path d = scratch("mark");
  World world(build_scene(j, "mark.json"));
  RunOptions opt;
  opt.out_dir = d.string();
  run_world(world, opt);
  const auto rows = lines_of(d / "timeseries.csv");
  const auto header = rows.at(0);
  std::size_t col = 0;
  for (std::size_t p = 0; p < header.find("V_over_V0"); ++p) col += header[p] == ',' ? 1 : 0;
  auto volume_at = [&](std::size_t step) {
    std::stringstream row(rows.at(step + 1));
    std::string cell;
    for (std::size_t c = 0; c <= col; ++c) std::getline(row, cell, ',');
    return std::stod(cell);
  };
  EXPECT_EQ(volume_at(800), 1.0);
  // s_p = 1 + 1e-2 * 100 * 0.005 after step 801: V/V0 = 1.005^3, not 1 (V0 not re-taken).
  EXPECT_NEAR(volume_at(801), 1.005 * 1.005 * 1.005, 1e-9);
  fs::remove_all(d);
}

}  // namespace
}  // namespace ratchet
