// Stage fields (run/stage_fields.hpp, outputs.displacement.stages): the displacement over
// each heating and each cooling, on spheres whose motion is known and on a small bed
// whose stage fields must add up to its cycle fields.
#include "ratchet/run/stage_fields.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <utility>

#include "../support/test_files.hpp"
#include "ratchet/run/runner.hpp"

namespace ratchet {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::fresh_dir;
using test::lines_of;

std::vector<double> cells_of(const std::string& row) {
  std::stringstream ss(row);
  std::vector<double> v;
  for (std::string c; std::getline(ss, c, ',');) v.push_back(std::stod(c));
  return v;
}

void run_into(const json& scene, const fs::path& d) {
  World world(build_scene(scene, "stages.json"));
  RunOptions opt;
  opt.out_dir = d.string();
  run_world(world, opt);
}

// Five spheres of radius 0.5 resting on the floor, apart (one on the axis, four at
// r = 2), growing by alpha_p (T1 - T0) = 10 % in a container that does not expand: each
// centre rises by 0.05 over the heating and sinks back by as much over the cooling, and
// nothing moves sideways.
json spheres_on_the_floor() {
  return json::parse(R"({
    "name": "stages", "time": {"dt": 0.004},
    "container": {"type": "cone", "bottom_radius": 4.0},
    "particles": {"bodies": [
      {"shape": "sphere", "radius": 0.5, "position": [0, 0, 0.5]},
      {"shape": "sphere", "radius": 0.5, "position": [2, 0, 0.5]},
      {"shape": "sphere", "radius": 0.5, "position": [0, 2, 0.5]},
      {"shape": "sphere", "radius": 0.5, "position": [-2, 0, 0.5]},
      {"shape": "sphere", "radius": 0.5, "position": [0, -2, 0.5]}]},
    "thermal": {"T0": 0, "T1": 100, "heat_time": 1.0, "hold_time": 0.5, "cool_time": 1.0, "cycles": 2,
                "alpha_p": 1e-3, "alpha_c": 0},
    "outputs": {"timeseries_every": 1000, "displacement": {"cell": 1.0, "windows": [[0, 1]], "stages": true}}
  })");
}

TEST(StageFields, SpheresRiseOnHeatingAndSinkOnCooling) {
  const fs::path d = fresh_dir("ratchet_stage_fields");
  run_into(spheres_on_the_floor(), d);
  const auto lines = lines_of(d / kStageFieldsFileName);
  ASSERT_EQ(lines.size(), 1u + 2u * 2u);  // header + 2 cycles x 2 populated cells
  EXPECT_EQ(lines[0], "cycle,ir,iz,r,z,count,ur_heating,uz_heating,ur_cooling,uz_cooling");
  const std::vector<std::pair<int, int>> cells = {{0, 1}, {2, 4}};  // (ir, count), all in iz = 0
  for (int cycle = 0; cycle < 2; ++cycle)
    for (std::size_t c = 0; c < 2; ++c) {
      const std::vector<double> v = cells_of(lines[1 + 2 * cycle + c]);
      ASSERT_EQ(v.size(), 10u);
      EXPECT_EQ(v[0], cycle);
      EXPECT_EQ(v[1], cells[c].first);
      EXPECT_EQ(v[2], 0);
      EXPECT_EQ(v[3], cells[c].first + 0.5);
      EXPECT_EQ(v[4], 0.5);
      EXPECT_EQ(v[5], cells[c].second);
      // 0.005 = 10 % of the rise: the gap relaxation (solver.p_gap) lets a growing
      // sphere lag its new radius by a small overlap; no force pushes it sideways.
      EXPECT_NEAR(v[7], 0.05, 0.005) << lines[1 + 2 * cycle + c];
      EXPECT_NEAR(v[9], -0.05, 0.005) << lines[1 + 2 * cycle + c];
      EXPECT_NEAR(v[6], 0.0, 1e-6);
      EXPECT_NEAR(v[8], 0.0, 1e-6);
    }
}

TEST(StageFields, NotAskedNotWritten) {
  const fs::path d = fresh_dir("ratchet_stage_fields");
  json j = spheres_on_the_floor();
  j["outputs"]["displacement"].erase("stages");
  run_into(j, d);
  EXPECT_FALSE(fs::exists(d / kStageFieldsFileName));
  EXPECT_TRUE(fs::exists(d / "displacement_0_1.csv"));
}

// A small bed with no hold: the end of cooling is the end of the cycle, so heating plus
// cooling (both binned where the bodies were at the start of the cycle) is the cycle's
// field of displacement_<k>_<k+1>.csv, cell by cell.
TEST(StageFields, HeatingPlusCoolingIsTheCycleField) {
  const fs::path d = fresh_dir("ratchet_stage_fields");
  const json j = json::parse(R"({
    "name": "chain", "seed": 3, "time": {"dt": 0.004},
    "solver": {"tolerance": 1e-4, "max_iterations": 200},
    "container": {"type": "cone", "bottom_radius": 3.0, "opening_angle_deg": 4.0},
    "particles": {"generate": {"count": 40, "shape": "polyhedron", "vertices": 12, "radius_range": [0.3, 0.5]}},
    "thermal": {"start_time": 4.0, "heat_time": 1.0, "hold_time": 0.0, "cool_time": 1.0, "cycles": 2,
                "alpha_p": 1e-4, "alpha_c": 1e-3},
    "outputs": {"timeseries_every": 1000, "displacement": {"cell": 1.0, "windows": [[0, 1], [1, 2]], "stages": true}}
  })");
  run_into(j, d);
  const auto stages = lines_of(d / kStageFieldsFileName);
  std::size_t compared = 0;
  for (int cycle = 0; cycle < 2; ++cycle) {
    std::map<std::pair<int, int>, std::vector<double>> window;  // (ir, iz) -> ir,iz,r,z,ur,uz,count,w
    const auto rows = lines_of(d / ("displacement_" + std::to_string(cycle) + "_" + std::to_string(cycle + 1) + ".csv"));
    for (std::size_t i = 1; i < rows.size(); ++i) {
      const auto v = cells_of(rows[i]);
      window[{static_cast<int>(v[0]), static_cast<int>(v[1])}] = v;
    }
    double moved = 0.0;
    for (std::size_t i = 1; i < stages.size(); ++i) {
      const auto s = cells_of(stages[i]);
      if (static_cast<int>(s[0]) != cycle) continue;
      const auto it = window.find({static_cast<int>(s[1]), static_cast<int>(s[2])});
      ASSERT_NE(it, window.end()) << stages[i];
      const auto& w = it->second;
      EXPECT_EQ(s[5], w[6]) << stages[i];  // count
      // 6 significant digits in stage_fields.csv: each term within 5e-6 of itself.
      EXPECT_NEAR(s[6] + s[8], w[4], 1e-5 * (std::abs(s[6]) + std::abs(s[8])) + 1e-300) << stages[i];
      EXPECT_NEAR(s[7] + s[9], w[5], 1e-5 * (std::abs(s[7]) + std::abs(s[9])) + 1e-300) << stages[i];
      moved = std::max({moved, std::abs(s[6]), std::abs(s[7])});
      ++compared;
    }
    EXPECT_GT(moved, 1e-4) << "cycle " << cycle << ": the bed should move";
  }
  EXPECT_GE(compared, 6u);  // a 40-body bed fills 3 to 4 cells of side 1 per cycle
}

}  // namespace
}  // namespace ratchet
