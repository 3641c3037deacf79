// ratchet: the command-line program of the NSCD reference engine.
//   ratchet run SCENE.json --out DIR [--packing FILE] [--set key.path=value ...] [--quiet]
//   ratchet run --explain SCENE.json [--set ...]
//   ratchet pack SCENE.json --out FILE [--set key.path=value ...] [--quiet]
//   ratchet sweep SWEEP.json --out DIR [--jobs N]
//   ratchet --version | help
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <mpi.h>

#include <cstdlib>
#include <filesystem>
#include <thread>

#include "cli_main.hpp"
#include "ratchet/io/state_file.hpp"
#include "ratchet/observe/energy.hpp"
#include "ratchet/run/packing.hpp"
#include "ratchet/run/run_output.hpp"
#include "ratchet/run/runner.hpp"
#include "ratchet/run/sweep.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/world/world.hpp"

namespace {

const char* kUsage =
    "usage:\n"
    "  ratchet run SCENE.json --out DIR [--packing FILE] [--set key.path=value ...] [--quiet]\n"
    "      run a scene; writes DIR/timeseries.csv, DIR/bodies.csv, DIR/run.json;\n"
    "      with --packing, start from that settled packing (made by ratchet pack)\n"
    "  ratchet run --explain SCENE.json [--set key.path=value ...]\n"
    "      print the phases the scene will run and why, then exit\n"
    "  ratchet pack SCENE.json --out FILE [--set key.path=value ...] [--quiet]\n"
    "      pour and settle the bed (until settle.ke_ratio, or up to thermal.start_time without a\n"
    "      settle section); write the packing to FILE\n"
    "  ratchet sweep SWEEP.json --out DIR [--jobs N]\n"
    "      run every point of a sweep (grid x realizations), N runs at a time (default: all cores);\n"
    "      under mpirun -n K the runs are spread over K ranks; writes DIR/packings/, DIR/runs/<id>/,\n"
    "      DIR/summary.csv\n"
    "  ratchet --version\n"
    "See docs/cli.md and docs/scene-format.md.\n";

int usage_error(const std::string& msg) {
  std::cerr << "ratchet: " << msg << "\n" << kUsage;
  return 2;
}

int explain(const ratchet::World& world) {
  const ratchet::SceneDef& s = world.scene();
  std::cout << "scene " << s.name << " (" << s.source << ", hash " << s.hash << ")\n"
            << "  " << s.bodies.size() << " bodies, " << s.container.walls.size() << " walls, h = " << s.dt
            << ", " << s.steps << " steps (duration " << s.duration << ")\n";
  if (world.settling())
    std::cout << "  settles until KE <= " << s.settle.ke_ratio << " x its peak (at most t = " << s.settle.max_time
              << "), then rests " << s.settle.rest_time << " and runs " << s.settle.run_time
              << " in all: the step count above is the most it can take\n";
  std::cout << "phases of each step:\n";
  int k = 1;
  for (const auto& p : world.plan())
    std::printf("  %d. %-14s %-4s %s\n", k++, p.name.c_str(), p.active ? "run" : "skip", p.reason.c_str());
  return 0;
}

// True when started by mpirun (OpenMPI or a PMI launcher): only then is MPI used.
bool launched_by_mpirun() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMI_SIZE") != nullptr ||
         std::getenv("PMIX_RANK") != nullptr;
}

int sweep(const std::vector<std::string>& args) {
  std::string sweep_path, out_dir;
  int jobs = 0;
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--out" || a == "--jobs") {
      if (i + 1 >= args.size()) return usage_error(a + " needs a value");
      if (a == "--out") out_dir = args[++i];
      else {
        jobs = std::atoi(args[++i].c_str());
        if (jobs < 1) return usage_error("--jobs needs a positive integer");
      }
    } else if (!a.empty() && a[0] == '-') return usage_error("unknown option '" + a + "'");
    else if (sweep_path.empty()) sweep_path = a;
    else return usage_error("more than one sweep file given");
  }
  if (sweep_path.empty() || out_dir.empty()) return usage_error("sweep needs SWEEP.json and --out DIR");
  const bool mpi = launched_by_mpirun();
  int rank = 0, size = 1;
  if (mpi) {
    MPI_Init(nullptr, nullptr);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
  }
  int status = 0;
  try {
    // Every rank checks the whole sweep before any run starts.
    const ratchet::SweepPlan plan = ratchet::load_sweep(sweep_path, out_dir);
    std::vector<int> mine;
    for (const auto& run : plan.runs)
      if (run.id % size == rank) mine.push_back(run.id);
    if (jobs == 0) jobs = size > 1 ? 1 : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    const std::string who = size > 1 ? "ratchet sweep [rank " + std::to_string(rank) + "]: " : "ratchet sweep: ";
    if (rank == 0)
      std::cerr << who << plan.runs.size() << " runs (" << plan.grid_keys.size() << " grid keys), " << size
                << " rank(s), " << jobs << " job(s) per rank -> " << out_dir << "\n";
    const auto say = [&](const std::string& line) { std::cerr << who << line << "\n"; };
    // Packings first, spread over the ranks like the runs; all ranks wait for all of them.
    const std::vector<int> needed = ratchet::needed_packings(plan);
    std::vector<int> my_packings;
    for (std::size_t k = 0; k < needed.size(); ++k)
      if (static_cast<int>(k % static_cast<std::size_t>(size)) == rank) my_packings.push_back(needed[k]);
    if (!plan.packings.empty()) ratchet::make_packings(plan, my_packings, jobs, say);
    if (mpi) MPI_Barrier(MPI_COMM_WORLD);
    ratchet::run_sweep(plan, mine, jobs, say);
    if (mpi) MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
      ratchet::write_sweep_summary(plan);
      std::cerr << who << "summary in " << out_dir << "/summary.csv\n";
      for (const auto& run : plan.runs)
        if (!ratchet::run_completed(plan, run)) status = 1;
      if (status != 0) std::cerr << who << "some runs did not complete (status 'missing' in summary.csv)\n";
    }
  } catch (const ratchet::SceneError& e) {
    std::cerr << "ratchet: error: " << e.what() << "\n";
    status = 2;
  } catch (const std::exception& e) {
    std::cerr << "ratchet: error: " << e.what() << "\n";
    status = 1;
  }
  if (mpi) {
    MPI_Allreduce(MPI_IN_PLACE, &status, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    MPI_Finalize();
  }
  return status;
}

}  // namespace

int ratchet_cli_main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "help" || args[0] == "--help" || args[0] == "-h") {
    std::cout << kUsage;
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version") {
    std::cout << "ratchet " << RATCHET_VERSION << " (" << RATCHET_BUILD_TYPE << ")\n";
    return 0;
  }
  if (args[0] == "sweep") return sweep(args);
  if (args[0] != "run" && args[0] != "pack") return usage_error("unknown command '" + args[0] + "'");
  const bool pack = args[0] == "pack";
  std::string scene_path, out_dir, packing;
  std::vector<std::string> overrides;
  bool do_explain = false, quiet = false;
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--explain" && !pack) do_explain = true;
    else if (a == "--quiet") quiet = true;
    else if (a == "--out" || a == "--set" || (a == "--packing" && !pack)) {
      if (i + 1 >= args.size()) return usage_error(a + " needs a value");
      (a == "--out" ? out_dir : a == "--packing" ? packing : (overrides.emplace_back(), overrides.back())) = args[++i];
    } else if (!a.empty() && a[0] == '-') return usage_error("unknown option '" + a + "'");
    else if (scene_path.empty()) scene_path = a;
    else return usage_error("more than one scene file given ('" + scene_path + "', '" + a + "')");
  }
  if (scene_path.empty()) return usage_error("no scene file given");
  if (pack && out_dir.empty()) return usage_error("--out FILE is required to pack a scene");
  if (pack && std::filesystem::is_directory(out_dir)) return usage_error("--out FILE names a folder: " + out_dir);
  if (!do_explain && out_dir.empty()) return usage_error("--out DIR is required to run a scene");
  try {
    // Everything that can reject the input happens before any output is created.
    const ratchet::SceneDef scene = ratchet::load_scene(scene_path, overrides);
#ifdef _OPENMP
    if (scene.solver.threads > 0) omp_set_num_threads(scene.solver.threads);
#endif
    if (pack && !ratchet::has_settle_stage(scene))
      throw ratchet::SceneError(scene.source + ": field 'thermal': expected a thermal section (a packing is the bed "
                                               "at the end of the settle stage)");
    ratchet::World world(scene);
    if (pack) {
      const auto t0 = std::chrono::steady_clock::now();
      auto last = t0;
      const bool progress = !quiet && isatty(STDERR_FILENO);
      bool printed = false;
      nlohmann::json settle;
      try {
        settle = ratchet::settle_world(world, [&](const ratchet::World& w) {
          const auto now = std::chrono::steady_clock::now();
          if (!progress || std::chrono::duration<double>(now - last).count() < 0.5) return;
          last = now;
          printed = true;
          std::fprintf(stderr, "\r%s: settling, t=%.4g of at most %.4g, KE=%.3g   ", scene.name.c_str(), w.state().t,
                       scene.settle.enabled ? scene.settle.max_time : scene.thermal.start_time,
                       ratchet::kinetic_energy(w.scene(), w.state()));
          std::fflush(stderr);
        });
      } catch (...) {
        if (printed) std::fprintf(stderr, "\n");  // the error starts a line of its own
        throw;
      }
      if (printed) std::fprintf(stderr, "\n");
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const std::filesystem::path parent = std::filesystem::path(out_dir).parent_path();
      if (!parent.empty()) std::filesystem::create_directories(parent);
      ratchet::write_packing(out_dir, world, settle, {{"wall_seconds", seconds}});
      if (!quiet)
        std::cerr << "ratchet: " << scene.name << ": packing " << ratchet::packing_key(scene) << " at t = "
                  << ratchet::format_double(world.state().t) << " (step " << world.state().step << "), KE/KE_peak = "
                  << settle.at("ke_ratio").dump() << ", in " << seconds << " s -> " << out_dir << "\n";
      return 0;
    }
    ratchet::RunOptions opt;
    if (!packing.empty()) {
      const nlohmann::json meta = ratchet::load_packing(packing, world);
      opt.packing = ratchet::packing_reference(packing, world);
      opt.packing_settle = meta.value("settle", nlohmann::json());
    }
    if (do_explain) {
      if (!packing.empty())
        std::cout << "starts from the packing " << packing << " (step " << world.state().step << ", t = "
                  << world.state().t << ")\n";
      return explain(world);
    }
    opt.out_dir = out_dir;
    opt.progress = !quiet && isatty(STDERR_FILENO);
    const ratchet::RunResult r = ratchet::run_world(world, opt);
    if (!quiet)
      std::cerr << "ratchet: " << scene.name << ": " << r.steps << " steps in " << r.wall_seconds << " s -> "
                << out_dir << "\n";
    return 0;
  } catch (const ratchet::SceneError& e) {
    std::cerr << "ratchet: error: " << e.what() << "\n";
    return 2;
  } catch (const ratchet::StateFileError& e) {  // a packing that is unreadable or of another scene: bad input
    std::cerr << "ratchet: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ratchet: error: " << e.what() << "\n";
    return 1;
  }
}
