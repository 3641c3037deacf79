// VTK snapshots of a run: which states are written (the first, every vtk_every steps,
// the last, the stage ends of vtk_cycles), the .pvd indexes with one entry per state,
// the container's forces against the step's statistics, that an earlier run's files go
// and others stay, and that writing VTK changes no bit of the run's results.
#include "ratchet/run/vtk_snapshots.hpp"
#include "ratchet/run/run_output.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_files.hpp"
#include "ratchet/run/runner.hpp"

namespace ratchet {
namespace {
using test::read_text;

namespace fs = std::filesystem;
using nlohmann::json;
using test::lines_of;

// 80 steps of h = 0.01: heating ends at t = 0.4 (step 40), cooling at t = 0.7 (step 70).
json cycled_cone() {
  return json::parse(R"({
    "name": "vtk", "time": {"dt": 0.01},
    "container": {"type": "cone", "bottom_radius": 2.0, "segments": 6, "height": 3.0},
    "particles": {"bodies": [
      {"shape": "sphere", "radius": 0.5, "position": [0.6, 0, 0.5]},
      {"shape": "sphere", "radius": 0.5, "position": [-0.6, 0, 0.5]},
      {"shape": "box", "half_extents": [0.3, 0.3, 0.3], "position": [0, 0, 1.4], "angular_velocity": [0, 0, 2]}]},
    "thermal": {"start_time": 0.2, "heat_time": 0.2, "hold_time": 0.1, "cool_time": 0.2, "cycles": 1,
                "alpha_p": 1e-3, "alpha_c": 1e-3},
    "outputs": {"vtk_every": 20, "vtk_cycles": [0]}
  })");
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("ratchet_vtk_snapshots_" + name);
  fs::remove_all(d);
  return d;
}

struct Indexed {
  std::vector<double> times;
  std::vector<std::string> files;
};

Indexed read_pvd(const fs::path& p) {
  const std::string text = read_text(p);
  static const std::regex dataset(R"re(<DataSet timestep="([^"]*)" group="" part="0" file="([^"]*)"/>)re");
  Indexed out;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), dataset); it != std::sregex_iterator(); ++it) {
    out.times.push_back(std::stod((*it)[1]));
    out.files.push_back((*it)[2]);
  }
  return out;
}

// The step field of a .vtp file.
long step_of(const fs::path& p) {
  const std::string text = read_text(p);
  static const std::regex step(R"re(Name="step" NumberOfTuples="1" format="ascii">\s*(-?\d+))re");
  std::smatch m;
  if (!std::regex_search(text, m, step)) return -1;
  return std::stol(m[1]);
}

TEST(VtkSnapshots, FirstEveryNLastAndStageEndsEachIndexedOnce) {
  const fs::path d = scratch("index");
  World world(build_scene(cycled_cone(), "vtk.json"));
  ASSERT_EQ(world.scene().steps, 80);
  RunOptions opt;
  opt.out_dir = d.string();
  run_world(world, opt);
  const std::vector<std::string> expected = {"step00000000", "step00000020", "step00000040", "step00000060",
                                             "cycle0_end_cooling", "step00000080"};
  const std::vector<long> steps = {0, 20, 40, 60, 70, 80};
  for (const std::string kind : {"particles", "contacts", "container", "force_chains"}) {
    const Indexed pvd = read_pvd(d / "vtk" / (kind + ".pvd"));
    ASSERT_EQ(pvd.files.size(), expected.size()) << kind;
    for (std::size_t i = 0; i < expected.size(); ++i) {
      EXPECT_EQ(pvd.files[i], kind + "_" + expected[i] + ".vtp");
      EXPECT_EQ(step_of(d / "vtk" / pvd.files[i]), steps[i]) << pvd.files[i];
      EXPECT_NEAR(pvd.times[i], 0.01 * static_cast<double>(steps[i]), 1e-12);
      if (i > 0) {
        EXPECT_GT(pvd.times[i], pvd.times[i - 1]);
      }
    }
    // The end of heating falls on step 40, a step of vtk_every: written under both names,
    // indexed under the first.
    EXPECT_EQ(step_of(d / "vtk" / (kind + "_cycle0_end_heating.vtp")), 40);
  }
  // Exactly these files: 7 tags x 4 kinds and 4 indexes, nothing half-written.
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(d / "vtk")) {
    ++files;
    EXPECT_EQ(e.path().string().find(".partial"), std::string::npos) << e.path();
  }
  EXPECT_EQ(files, 7u * 4u + 4u);
  fs::remove_all(d);
}

TEST(VtkSnapshots, TheContainerCarriesTheStepsWallForces) {
  World world(build_scene(cycled_cone(), "vtk.json"));
  for (int k = 0; k < 36; ++k) world.step();  // heating: the box rests on the two spheres
  const VtkSnapshot snap = take_vtk_snapshot(world);
  EXPECT_EQ(snap.time.step, 36);
  EXPECT_EQ(snap.time.t, world.state().t);
  ASSERT_EQ(snap.container.polygons.size(), 7u);
  ASSERT_EQ(snap.wall_force.size(), 7u);
  double side = 0.0;
  for (std::size_t p = 1; p < 7; ++p) side += snap.wall_force[p];
  EXPECT_GT(snap.wall_force[0], 0.0);  // the bed rests on the floor
  EXPECT_NEAR(snap.wall_force[0], world.stats().wall_force_bottom, 1e-12 * world.stats().wall_force_bottom);
  EXPECT_NEAR(side, world.stats().wall_force_side, 1e-12 * (1.0 + world.stats().wall_force_side));
  // Every detected contact point is there, the open ones too; the positive ones are the
  // step's count.
  ASSERT_EQ(snap.contacts.size(), world.contacts().size());
  int active = 0;
  for (const VtkContact& c : snap.contacts) active += c.normal.dot(c.normal_force) > 0.0 ? 1 : 0;
  EXPECT_EQ(active, world.stats().contacts);
  // Bodies: the state's velocities and scales.
  ASSERT_EQ(snap.bodies.size(), 3u);
  EXPECT_EQ(snap.bodies[2].angular_velocity, world.state().w[2]);
  EXPECT_EQ(snap.bodies[2].vertices.size(), 8u);
  EXPECT_EQ(snap.bodies[0].scale, world.state().s_p);
  EXPECT_EQ(snap.bodies[0].vertices, std::vector<Vec3>{world.state().x[0]});
}

TEST(VtkSnapshots, WritingVtkChangesNoBitOfTheResults) {
  json quiet = cycled_cone();
  quiet["outputs"] = {{"bodies_every", 1}};
  json loud = cycled_cone();
  loud["outputs"]["bodies_every"] = 1;
  loud["outputs"]["vtk_every"] = 1;
  std::vector<std::vector<std::string>> bodies, series;
  for (const bool vtk : {false, true}) {
    const json& j = vtk ? loud : quiet;
    const fs::path d = scratch("bits");
    World world(build_scene(j, "vtk.json"));
    RunOptions opt;
    opt.out_dir = d.string();
    run_world(world, opt);
    bodies.push_back(lines_of(d / "bodies.csv"));
    // timeseries.csv without the time_* columns (wall-clock times of the phases).
    std::vector<std::string> rows = lines_of(d / "timeseries.csv");
    std::vector<bool> keep;
    std::stringstream header(rows.at(0));
    for (std::string c; std::getline(header, c, ',');) keep.push_back(c.rfind("time_", 0) != 0);
    for (std::string& row : rows) {
      std::stringstream in(row);
      std::string kept, c;
      for (std::size_t i = 0; std::getline(in, c, ','); ++i)
        if (keep.at(i)) kept += c + ',';
      row = kept;
    }
    series.push_back(rows);
    EXPECT_EQ(fs::exists(d / "vtk"), vtk);
    fs::remove_all(d);
  }
  EXPECT_EQ(bodies[0].size(), 3u * 81u + 1u);
  EXPECT_EQ(bodies[0], bodies[1]);
  EXPECT_EQ(series[0], series[1]);
}

TEST(VtkSnapshots, NoContainerNoContainerFiles) {
  json j = cycled_cone();
  j.erase("container");
  j.erase("thermal");
  j["time"]["duration"] = 0.1;
  j["outputs"] = {{"vtk_every", 5}};
  const fs::path d = scratch("free");
  World world(build_scene(j, "free.json"));
  RunOptions opt;
  opt.out_dir = d.string();
  run_world(world, opt);
  EXPECT_EQ(read_pvd(d / "vtk" / "particles.pvd").files.size(), 3u);  // steps 0, 5, 10
  EXPECT_TRUE(fs::exists(d / "vtk" / "contacts_step00000010.vtp"));
  EXPECT_FALSE(fs::exists(d / "vtk" / "container.pvd"));
  EXPECT_FALSE(fs::exists(d / "vtk" / "container_step00000000.vtp"));
  fs::remove_all(d);
}

TEST(VtkSnapshots, AnEarlierRunsSnapshotsGoOtherFilesStay) {
  const fs::path d = scratch("previous");
  fs::create_directories(d / "vtk");
  const std::vector<std::string> doomed = {"particles.pvd", "contacts.pvd", "container.pvd.partial",
                                           "particles_step00000100.vtp", "contacts_cycle3_end_heating.vtp",
                                           "container_step00000000.vtp.partial"};
  const std::vector<std::string> kept = {"notes.txt", "mine.vtp", "particles.pvd.bak", "container_x.vtu"};
  for (const auto& f : doomed) std::ofstream(d / "vtk" / f) << "old";
  for (const auto& f : kept) std::ofstream(d / "vtk" / f) << "mine";
  EXPECT_EQ(remove_previous_outputs(d.string()).size(), doomed.size());
  for (const auto& f : doomed) EXPECT_FALSE(fs::exists(d / "vtk" / f)) << f;
  for (const auto& f : kept) EXPECT_TRUE(fs::exists(d / "vtk" / f)) << f;
  // A run with VTK off still clears them (its folder must not index an older run).
  std::ofstream(d / "vtk" / "particles.pvd") << "old";
  json j = cycled_cone();
  j["outputs"] = json::object();
  j["time"]["duration"] = 0.05;
  World world(build_scene(j, "vtk.json"));
  RunOptions opt;
  opt.out_dir = d.string();
  run_world(world, opt);
  EXPECT_FALSE(fs::exists(d / "vtk" / "particles.pvd"));
  EXPECT_TRUE(fs::exists(d / "vtk" / "notes.txt"));
  fs::remove_all(d);
}

TEST(VtkSnapshots, StepTagsSortAsNumbers) {
  EXPECT_EQ(vtk_step_tag(0), "step00000000");
  EXPECT_EQ(vtk_step_tag(1200), "step00001200");
  EXPECT_EQ(vtk_step_tag(123456789), "step123456789");
}

}  // namespace
}  // namespace ratchet
