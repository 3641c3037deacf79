// The run's files: round-trip number format, the header with the observers' columns,
// rows in order, .partial names until finish, and run.json with the summary.
#include "ratchet/run/run_output.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "support/test_files.hpp"

namespace ratchet {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

using test::lines_of;

SceneDef one_sphere() {
  return build_scene(json::parse(R"({
    "name": "out", "time": {"dt": 0.01, "duration": 0.05},
    "container": {"type": "planes", "planes": [{"normal": [0, 0, 1], "point": [0, 0, 0]}]},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 2]}]}
  })"),
                     "out.json");
}

TEST(FormatDouble, SeventeenDigitsReadBackExactly) {
  EXPECT_EQ(format_double(0.1), "0.10000000000000001");
  EXPECT_EQ(format_double(2.0), "2");
  for (double x : {1.0 / 3.0, -2.5e-300, 6.02214076e23, std::nextafter(1.0, 2.0)})
    EXPECT_EQ(std::stod(format_double(x)), x) << format_double(x);
  EXPECT_EQ(format_double(std::numeric_limits<double>::infinity()), "inf");
}

TEST(RunOutput, WritesHeaderRowsAndRunJson) {
  const fs::path d = fs::temp_directory_path() / "ratchet_run_output_test";
  fs::remove_all(d);
  fs::create_directories(d);
  std::ofstream(d / "run.json") << "{\"status\": \"completed\"}\n";  // a stale one
  World world(one_sphere());
  remove_previous_outputs(d.string());  // as the runner does first
  EXPECT_FALSE(fs::exists(d / "run.json"));  // no longer looks complete
  {
    RunOutput out(d.string(), {"extra_a", "extra_b"});
    out.write_timeseries_row(world, {1.5, 2.5});
    out.write_bodies(world);
    world.step();
    out.write_timeseries_row(world, {3.5, 4.5});
    EXPECT_FALSE(fs::exists(d / "timeseries.csv"));  // still .partial
    EXPECT_TRUE(fs::exists(d / "timeseries.csv.partial"));
    out.finish(world, {{"status", "completed"}, {"summary", {{"x", 1}}}});
  }
  const auto ts = lines_of(d / "timeseries.csv");
  ASSERT_EQ(ts.size(), 3u);
  EXPECT_EQ(ts[0].rfind("step,t,T,s_p,s_c,kinetic_energy,", 0), 0u);
  EXPECT_EQ(ts[0].substr(ts[0].size() - 16), ",extra_a,extra_b");
  EXPECT_EQ(ts[1].rfind("0,0,", 0), 0u);
  EXPECT_EQ(ts[1].substr(ts[1].size() - 8), ",1.5,2.5");
  EXPECT_EQ(ts[2].rfind("1,0.01,", 0), 0u);
  EXPECT_EQ(ts[2].substr(ts[2].size() - 8), ",3.5,4.5");
  const auto bodies = lines_of(d / "bodies.csv");
  ASSERT_EQ(bodies.size(), 2u);
  EXPECT_EQ(bodies[1], "0,0,0,0,0,2,1,0,0,0,0,0,0,0,0,0,1");
  std::ifstream in(d / "run.json");
  const json meta = json::parse(in);
  EXPECT_EQ(meta.at("status"), "completed");
  EXPECT_EQ(meta.at("summary").at("x"), 1);
  EXPECT_EQ(meta.at("steps"), 1);
  EXPECT_EQ(meta.at("bodies"), 1);
  EXPECT_EQ(meta.at("scene_hash"), world.scene().hash);
  EXPECT_EQ(meta.at("engine").at("name"), "ratchet");
  fs::remove_all(d);
}

TEST(RunOutput, ClearsAnEarlierRunsOutputsAndNothingElse) {
  const fs::path d = fs::temp_directory_path() / "ratchet_run_output_stale_test";
  fs::remove_all(d);
  fs::create_directories(d / "vtk");
  const std::vector<std::string> stale = {"run.json", "cycles.csv", "wall_profile.csv", "displacement_0_10.csv",
                                          "stage_fields.csv", "timeseries.csv.partial",
                                          "vtk/particles_cycle1_end_heating.vtk",
                                          "vtk/contacts_cycle1_end_cooling.vtp", "vtk/particles.pvd"};
  const std::vector<std::string> kept = {"notes.txt", "packing.state", "cycles.csv.bak", "vtk/mine.vtk",
                                         "displacement_.csv"};
  for (const auto& name : stale) std::ofstream(d / name) << "old\n";
  for (const auto& name : kept) std::ofstream(d / name) << "mine\n";
  World world(one_sphere());
  EXPECT_EQ(remove_previous_outputs(d.string()).size(), stale.size());
  {
    RunOutput out(d.string(), {});
    for (const auto& name : stale) {
      if (name == "timeseries.csv.partial") continue;  // this run's own now
      EXPECT_FALSE(fs::exists(d / name)) << name;
    }
    for (const auto& name : kept) EXPECT_TRUE(fs::exists(d / name)) << name;
    out.write_timeseries_row(world, {});
    out.finish(world, {{"status", "completed"}});
  }
  // The run without cycles leaves no cycles.csv of the earlier one behind.
  EXPECT_FALSE(fs::exists(d / "cycles.csv"));
  EXPECT_EQ(lines_of(d / "timeseries.csv").size(), 2u);
  fs::remove_all(d);
}

TEST(RunOutput, RemovesRunJsonFirst) {
  const fs::path d = fs::temp_directory_path() / "ratchet_run_output_order_test";
  fs::remove_all(d);
  fs::create_directories(d);
  for (const char* name : {"bodies.csv", "run.json", "timeseries.csv"}) std::ofstream(d / name) << "old\n";
  const auto removed = remove_previous_outputs(d.string());
  ASSERT_EQ(removed.size(), 3u);
  EXPECT_EQ(fs::path(removed.front()).filename(), "run.json");  // a crash midway never looks complete
  fs::remove_all(d);
}

}  // namespace
}  // namespace ratchet
