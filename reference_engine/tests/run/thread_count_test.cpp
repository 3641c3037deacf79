// The same scene and seed give the same bytes on any number of threads: a bed of
// polyhedra poured and settled once, then heated and cooled from that packing (compliant
// Anderson sweeps and manifold replay as the paper tier) on 1, 2, 3 and 8 threads, with the solve's parallel loops
// forced on at any size (world/test_hooks.hpp) so that the coloured sweep, the Anderson
// passes and the row build all split their work. timeseries.csv is compared without its
// time_* columns, the wall-clock time of each phase. (The pour runs the same code; it is
// left out because 8 threads on a 2-core machine make its thousands of small steps slow.)
#include <gtest/gtest.h>
#include <omp.h>

#include <filesystem>

#include "../support/test_files.hpp"
#include "ratchet/run/packing.hpp"
#include "ratchet/run/run_output.hpp"
#include "ratchet/run/runner.hpp"
#include "ratchet/world/test_hooks.hpp"

namespace ratchet {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::without_timing_columns;

json cycled_bed() {
  return json::parse(R"({
    "name": "threads", "seed": 9, "time": {"dt": 0.004},
    "solver": {"tolerance": 1e-4, "max_iterations": 2000, "acceleration": "anderson", "compliance": 0.1,
               "manifold_reuse": 0.002},
    "container": {"type": "cone", "bottom_radius": 3.0, "opening_angle_deg": 4.0, "segments": 8},
    "particles": {"generate": {"count": 50, "shape": "polyhedron", "vertices": 12, "radius_range": [0.3, 0.5]}},
    "settle": {"ke_ratio": 1e-2, "max_time": 10.0},
    "thermal": {"start_time": 0.2, "heat_time": 0.6, "hold_time": 0.1, "cool_time": 0.6, "cycles": 1,
                "alpha_p": 1e-4, "alpha_c": 1e-3},
    "outputs": {"timeseries_every": 1, "bodies_every": 100}
  })");
}


// The bytes of each thread count, in the order given (the packing poured by the first).
struct ThreadRuns {
  std::vector<std::string> series, bodies;
  int most_colours = 0;
};

ThreadRuns run_on_threads(const json& scene_json, const std::vector<int>& counts, const std::string& name) {
  const int saved_threads = omp_get_max_threads();
  const SceneDef scene = build_scene(scene_json, name + ".json");
  const fs::path packing = test::fresh_dir("ratchet_" + name + "_packing") / "bed.state";
  {
    World world(scene);
    write_packing(packing.string(), world, settle_world(world), json::object());
  }
  test_hooks().parallel_min_rows = 0;
  ThreadRuns out;
  for (int threads : counts) {
    omp_set_num_threads(threads);
    const fs::path dir = test::fresh_dir("ratchet_" + name + "_" + std::to_string(threads));
    World world(scene);
    RunOptions opt;
    opt.packing_settle = load_packing(packing.string(), world).value("settle", json());
    opt.packing = packing_reference(packing.string(), world);
    opt.out_dir = dir.string();
    run_world(world, opt, [&](const World& w) {
      out.most_colours = std::max(out.most_colours, w.contact_colouring().colours());
    });
    out.series.push_back(without_timing_columns(test::read_text(dir / "timeseries.csv")));
    out.bodies.push_back(test::read_text(dir / "bodies.csv"));
    fs::remove_all(dir);
  }
  test_hooks().parallel_min_rows = -1;
  omp_set_num_threads(saved_threads);
  fs::remove_all(packing.parent_path());
  return out;
}

// The inexact slide (solver.slide_newton_steps) holds budgeted and exact lanes in one
// batch (solver/nsgs.cpp, SlideBatch): the same bytes on 1 and 3 threads too, and other
// bytes than the exact slide's (the budget binds).
TEST(ThreadCount, TheInexactSlideWritesTheSameBytesOnOneAndThreeThreads) {
  json scene = cycled_bed();
  scene["solver"]["slide_newton_steps"] = 1;
  const ThreadRuns inexact = run_on_threads(scene, {1, 3}, "threads_slide");
  const ThreadRuns exact = run_on_threads(cycled_bed(), {1}, "threads_exact");
  EXPECT_GT(inexact.series[0].size(), 50000u);
  EXPECT_TRUE(inexact.series[1] == inexact.series[0]) << "timeseries.csv differs between 1 and 3 threads";
  EXPECT_TRUE(inexact.bodies[1] == inexact.bodies[0]) << "bodies.csv differs between 1 and 3 threads";
  EXPECT_FALSE(inexact.bodies[0] == exact.bodies[0]) << "the step budget never bound";
}

TEST(ThreadCount, OneTwoThreeAndEightThreadsWriteTheSameBytes) {
  const ThreadRuns runs = run_on_threads(cycled_bed(), {1, 2, 3, 8}, "threads");
  EXPECT_GT(runs.series[0].size(), 50000u);  // hundreds of steps, one row each
  EXPECT_GT(runs.most_colours, 3);           // the sweep really had several colours to split
  for (std::size_t k = 1; k < runs.series.size(); ++k) {
    EXPECT_TRUE(runs.series[k] == runs.series[0]) << "timeseries.csv differs at thread count index " << k;
    EXPECT_TRUE(runs.bodies[k] == runs.bodies[0]) << "bodies.csv differs at thread count index " << k;
  }
}

}  // namespace
}  // namespace ratchet
