// ratchet: the command-line program of the NSCD reference engine (docs/cli.md).
//   ratchet run SCENE.json --out DIR [--packing FILE] [--set key.path=value ...] [--quiet]
//   ratchet run --explain SCENE.json [--packing FILE] [--set ...]
//   ratchet run --resume DIR [--quiet]
//   ratchet pack SCENE.json --out FILE [--set key.path=value ...] [--quiet]
//   ratchet bodies SCENE.json --out FILE.json [--set key.path=value ...] [--quiet]
//   ratchet sweep SWEEP.json --out DIR [--jobs N] [--threads T] [--set key.path=value ...]
//   ratchet --version | -V | version,  ratchet help [COMMAND] | --help | -h,  ratchet COMMAND --help
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
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
#include "ratchet/core/build_info.hpp"
#include "ratchet/io/bodies_file.hpp"
#include "ratchet/io/state_file.hpp"
#include "ratchet/observe/energy.hpp"
#include "ratchet/run/checkpoint.hpp"
#include "ratchet/run/packing.hpp"
#include "ratchet/run/run_output.hpp"
#include "ratchet/run/runner.hpp"
#include "ratchet/run/stop_request.hpp"
#include "ratchet/run/sweep.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/world/world.hpp"

namespace {

namespace fs = std::filesystem;

// `ratchet --version`: the release and build type, then what built this binary
// (core/build_info.hpp), so that a script can tell whether it was built from the
// sources beside it (scripts/campaign_lib/engine.py recomputes the source hash).
std::string version_text() {
  return std::string("ratchet " RATCHET_VERSION " (" RATCHET_BUILD_TYPE ")\n") + "commit: " + ratchet::engine_commit() +
         "\nsource hash: " + ratchet::engine_source_hash() + "\ncompiler: " + ratchet::engine_compiler() + "\n";
}

// The synopsis of each command: its part of the usage, the first lines of its --help,
// and what follows a usage error of that command.
const std::map<std::string, std::string> kSynopsis = {
    {"run",
     "  ratchet run SCENE.json --out DIR [--packing FILE] [--set key.path=value ...] [--quiet]\n"
     "  ratchet run --explain SCENE.json [--packing FILE] [--set key.path=value ...]\n"
     "  ratchet run --resume DIR [--quiet]\n"},
    {"pack", "  ratchet pack SCENE.json --out FILE [--set key.path=value ...] [--quiet]\n"},
    {"bodies", "  ratchet bodies SCENE.json --out FILE.json [--set key.path=value ...] [--quiet]\n"},
    {"sweep", "  ratchet sweep SWEEP.json --out DIR [--jobs N] [--threads T] [--set key.path=value ...]\n"},
    {"help", "  ratchet help [COMMAND]\n"},
    {"version", "  ratchet version\n"},
};

const char* kUsage =
    "usage:\n"
    "  ratchet run SCENE.json --out DIR [--packing FILE] [--set key.path=value ...] [--quiet]\n"
    "      run a scene; writes DIR/timeseries.csv, DIR/bodies.csv, DIR/bodies_shapes.json,\n"
    "      DIR/run.json; with --packing, start from that settled packing (made by ratchet pack)\n"
    "  ratchet run --explain SCENE.json [--packing FILE] [--set key.path=value ...]\n"
    "      print the phases the scene will run and why, then exit\n"
    "  ratchet run --resume DIR [--quiet]\n"
    "      continue a run stopped by SIGINT/SIGTERM or killed, from DIR/checkpoint.state; the\n"
    "      result is the same, byte for byte, as if it had never stopped\n"
    "  ratchet pack SCENE.json --out FILE [--set key.path=value ...] [--quiet]\n"
    "      pour and settle the bed (until settle.ke_ratio, or up to thermal.start_time without a\n"
    "      settle section); write the packing to FILE; stopped by SIGINT/SIGTERM or killed, the\n"
    "      same command goes on from FILE.pour-checkpoint\n"
    "  ratchet bodies SCENE.json --out FILE.json [--set key.path=value ...] [--quiet]\n"
    "      build the scene as run does and write its bodies and shapes (poses, mass properties,\n"
    "      vertices) to FILE.json\n"
    "  ratchet sweep SWEEP.json --out DIR [--jobs N] [--threads T] [--set key.path=value ...]\n"
    "      run every point of a sweep (grid x realizations), N runs at a time (default: all cores),\n"
    "      each on T threads (default 1; the same results for any T);\n"
    "      under mpirun -n K the runs are spread over K ranks; writes DIR/packings/, DIR/runs/<id>/,\n"
    "      DIR/summary.csv; --set changes the base scene of every run\n"
    "  ratchet --version | -V | version\n"
    "      print the version and build type\n"
    "  ratchet help [COMMAND] | --help | -h\n"
    "      print this usage, or the options of COMMAND (as ratchet COMMAND --help)\n"
    "See docs/cli.md and docs/scene-format.md.\n";

// CLI11's help, with the command's synopsis as its usage line.
class Formatter : public CLI::Formatter {
 public:
  std::string make_usage(const CLI::App* app, std::string name) const override {
    const auto it = kSynopsis.find(app->get_name());
    return it == kSynopsis.end() ? CLI::Formatter::make_usage(app, name) : "usage:\n" + it->second;
  }
};

// Usage errors: the message, then the usage of the command (or all of it), on stderr.
int usage_error(const std::string& msg, const std::string& command = "") {
  std::cerr << "ratchet: " << msg << "\n";
  const auto it = kSynopsis.find(command);
  if (it == kSynopsis.end()) std::cerr << kUsage;
  else std::cerr << "usage:\n" << it->second << "Run 'ratchet " << command << " --help' for its options.\n";
  return 2;
}

// Input errors found before any work: one line, no usage.
int input_error(const std::string& msg) {
  std::cerr << "ratchet: error: " << msg << "\n";
  return 2;
}

// A whole number >= 1 written in decimal digits only; "2x", "0", "-1", "1.5", "" and
// out-of-range values give nullopt rather than being read in part.
std::optional<int> positive_int(const std::string& text) {
  int n = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, n);
  if (text.empty() || ec != std::errc() || ptr != end || n < 1) return std::nullopt;
  return n;
}

// Why `dir` can neither be used as a folder nor created as one, or "" when it can.
// Checked before any work, so that a bad --out does not fail after a long run.
std::string folder_problem(const fs::path& dir) {
  std::error_code ec;
  const auto kind = [](const fs::path& p) {
    std::error_code e;
    return fs::is_regular_file(p, e) ? "a file" : "not a folder";
  };
  if (fs::exists(dir, ec)) return fs::is_directory(dir, ec) ? "" : dir.string() + " is " + kind(dir);
  // The nearest part of the path that exists must be a folder we may write in.
  fs::path up = dir.parent_path();
  while (!up.empty() && !fs::exists(up, ec)) up = up.parent_path();
  if (up.empty()) up = ".";
  if (!fs::is_directory(up, ec)) return up.string() + " is " + kind(up);
  if (access(up.c_str(), W_OK | X_OK) != 0)
    return "no folder can be created in " + up.string() + " (" + std::strerror(errno) + ")";
  return "";
}

// Why `out` cannot be an output file (`what`: "the packing", "the bodies file"), or ""
// when it can: a folder, or a path whose folder is a file or cannot be created.
std::string file_problem(const std::string& out, const std::string& what) {
  const fs::path file(out), parent = file.parent_path().empty() ? fs::path(".") : file.parent_path();
  std::error_code ec;
  if (fs::is_directory(file, ec) || !file.has_filename())
    return "--out " + out + ": expected a file (" + what + "), but it names a folder";
  const std::string problem = folder_problem(parent);
  if (!problem.empty())
    return "--out " + out + ": expected a file in a folder that exists or can be created, but " + problem;
  return "";
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

// The arguments have been checked (ratchet_cli_main); jobs 0: the default.
int sweep(const std::string& sweep_path, const std::string& out_dir, int jobs, int threads,
          const std::vector<std::string>& overrides, const std::vector<std::string>& command_line) {
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
    ratchet::SweepPlan plan = ratchet::load_sweep(sweep_path, out_dir, overrides);
    plan.command_line = command_line;
    std::vector<int> mine;
    for (const auto& run : plan.runs)
      if (run.id % size == rank) mine.push_back(run.id);
    if (jobs == 0) jobs = size > 1 ? 1 : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    const std::string who = size > 1 ? "ratchet sweep [rank " + std::to_string(rank) + "]: " : "ratchet sweep: ";
    if (rank == 0)
      std::cerr << who << plan.runs.size() << " runs (" << plan.grid_keys.size() << " grid keys), " << size
                << " rank(s), " << jobs << " job(s) per rank, " << threads << " thread(s) per run -> " << out_dir
                << "\n";
    const auto say = [&](const std::string& line) { std::cerr << who << line << "\n"; };
    // Packings first, spread over the ranks like the runs; all ranks wait for all of them.
    const std::vector<int> needed = ratchet::needed_packings(plan);
    std::vector<int> my_packings;
    for (std::size_t k = 0; k < needed.size(); ++k)
      if (static_cast<int>(k % static_cast<std::size_t>(size)) == rank) my_packings.push_back(needed[k]);
    // SIGINT/SIGTERM stop each pour and run under way at a checkpoint, and start no other.
    ratchet::install_stop_handlers();
    if (!plan.packings.empty()) ratchet::make_packings(plan, my_packings, jobs, say, threads);
    if (mpi) MPI_Barrier(MPI_COMM_WORLD);
    ratchet::run_sweep(plan, mine, jobs, say, threads);
    if (const int sig = ratchet::stop_signal(); sig != 0) {
      std::cerr << who << "stopped by " << ratchet::signal_name(sig)
                << "; the pours and runs under way kept their checkpoints: run the same command again to resume\n";
      status = 128 + sig;
    }
    if (mpi) MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
      ratchet::write_sweep_summary(plan);
      std::cerr << who << "summary in " << out_dir << "/summary.csv\n";
      if (status == 0) {  // a stopped sweep has said so
        for (const auto& run : plan.runs)
          if (!ratchet::run_completed(plan, run)) status = 1;
        if (status != 0) std::cerr << who << "some runs did not complete (status 'missing' in summary.csv)\n";
      }
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

// What `run` and `pack` were given.
struct SceneArgs {
  std::string scene;
  std::string out, packing, resume;
  std::vector<std::string> overrides;
  bool explain = false, quiet = false;
  double progress_every = 60.0;  // off a terminal: seconds between progress lines
  std::vector<std::string> command_line;  // the program's arguments (run.json provenance)
};

// A run stopped by a signal: where it stands, and the conventional status 128 + signal.
int interrupted(const ratchet::RunInterrupted& e, const std::string& out_dir) {
  std::cerr << "ratchet: " << e.what() << "; resume with: ratchet run --resume " << out_dir << "\n";
  return 128 + e.signal;
}

// `ratchet run --resume DIR`: the run continues from DIR/checkpoint.state.
int resume_run(const SceneArgs& a) {
  const std::string command = "run";
  if (!a.scene.empty() || !a.out.empty() || !a.packing.empty() || !a.overrides.empty() || a.explain)
    return usage_error("--resume continues a run as it was: no scene file, --out, --packing, --set or --explain",
                       command);
  const std::string& dir = a.resume;
  if (!fs::is_directory(dir)) return input_error("--resume " + dir + ": expected the folder of a run, not found");
  try {
    std::ifstream in(dir + "/run.json");
    const nlohmann::json done = in ? nlohmann::json::parse(in, nullptr, false) : nlohmann::json();
    if (done.is_object() && done.value("status", "") == "completed")
      return input_error("--resume " + dir + ": the run is already completed (run.json)");
    const ratchet::ResumePoint point = ratchet::read_checkpoint(dir);
#ifdef _OPENMP
    if (point.scene.solver.threads > 0) omp_set_num_threads(point.scene.solver.threads);
#endif
    ratchet::World world(point.scene);
    ratchet::resume_world(world, point);
    ratchet::RunOptions opt;
    opt.out_dir = dir;
    opt.resume = point.run;
    opt.command_line = a.command_line;
    opt.progress = !a.quiet;
    opt.log_every = a.progress_every;
    ratchet::install_stop_handlers();
    if (!a.quiet)
      std::cerr << "ratchet: " << point.scene.name << ": resuming at step " << world.state().step << " of "
                << world.scene().steps << " from " << point.path << "\n";
    const ratchet::RunResult r = ratchet::run_world(world, opt);
    if (!a.quiet)
      std::cerr << "ratchet: " << point.scene.name << ": " << r.steps << " steps -> " << dir << "\n";
    return 0;
  } catch (const ratchet::RunInterrupted& e) {
    return interrupted(e, dir);
  } catch (const ratchet::SceneError& e) {
    std::cerr << "ratchet: error: " << e.what() << "\n";
    return 2;
  } catch (const ratchet::StateFileError& e) {
    std::cerr << "ratchet: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ratchet: error: " << e.what() << "\n";
    return 1;
  }
}

int run_or_pack(const bool pack, const SceneArgs& a) {
  const std::string command = pack ? "pack" : "run";
  if (!pack && !a.resume.empty()) return resume_run(a);
  const std::string& out_dir = a.out;
  const std::string& packing = a.packing;
  const bool do_explain = a.explain, quiet = a.quiet;
  if (a.scene.empty()) return usage_error("no scene file given", command);
  const std::string& scene_path = a.scene;
  if (pack && out_dir.empty()) return usage_error("--out FILE is required to pack a scene", command);
  if (!do_explain && out_dir.empty()) return usage_error("--out DIR is required to run a scene", command);
  if (pack) {
    const std::string problem = file_problem(out_dir, "the packing");
    if (!problem.empty()) return input_error(problem);
  } else if (!do_explain) {  // with --explain, --out is ignored
    const std::string problem = folder_problem(out_dir);
    if (!problem.empty())
      return input_error("--out " + out_dir + ": expected a folder, or a path where one can be created, but " +
                         problem);
  }
  try {
    // Everything that can reject the input happens before any output is created.
    const ratchet::SceneDef scene = ratchet::load_scene(scene_path, a.overrides);
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
      // A long pour keeps a checkpoint next to the packing and goes on from it when the
      // same command runs again (run/pour_checkpoint.hpp).
      const ratchet::PourCheckpointing checkpoints = ratchet::pour_checkpointing(out_dir, scene);
      ratchet::install_stop_handlers();
      try {
        const std::filesystem::path parent = std::filesystem::path(out_dir).parent_path();
        if (!parent.empty()) std::filesystem::create_directories(parent);
        settle = ratchet::settle_world(world, [&](const ratchet::World& w) {
          const auto now = std::chrono::steady_clock::now();
          if (!progress || std::chrono::duration<double>(now - last).count() < 0.5) return;
          last = now;
          printed = true;
          char tail[160];
          std::snprintf(tail, sizeof tail, ": settling, t=%.4g of at most %.4g, KE=%.3g", w.state().t,
                        scene.settle.enabled ? scene.settle.max_time : scene.thermal.start_time,
                        ratchet::kinetic_energy(w.scene(), w.state()));
          // Cut to the terminal and cleared to its end, as run's line (run/runner.hpp).
          std::fputs(ratchet::progress_line(scene.name + tail, ratchet::terminal_columns(STDERR_FILENO)).c_str(), stderr);
          std::fflush(stderr);
        }, checkpoints, [&](const std::string& line) {
          if (!quiet) std::cerr << "ratchet: " << scene.name << ": " << line << "\n";
        });
      } catch (const ratchet::RunInterrupted& e) {
        if (printed) std::fprintf(stderr, "\n");
        std::cerr << "ratchet: " << e.what() << "; run the same command again to resume\n";
        return 128 + e.signal;
      } catch (...) {
        if (printed) std::fprintf(stderr, "\n");  // the error starts a line of its own
        throw;
      }
      if (printed) std::fprintf(stderr, "\n");
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      ratchet::write_packing(out_dir, world, settle, {{"wall_seconds", seconds}});
      ratchet::remove_pour_checkpoint(checkpoints);  // the packing is written: the pour is done
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
    opt.command_line = a.command_line;
    opt.progress = !quiet;
    opt.log_every = a.progress_every;
    ratchet::install_stop_handlers();
    const ratchet::RunResult r = ratchet::run_world(world, opt);
    if (!quiet)
      std::cerr << "ratchet: " << scene.name << ": " << r.steps << " steps in " << r.wall_seconds << " s -> "
                << out_dir << "\n";
    return 0;
  } catch (const ratchet::RunInterrupted& e) {
    return interrupted(e, out_dir);
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

// `ratchet bodies`: the scene built as `run` builds it (same parser, seed and --set
// overrides, the world's initial state), its bodies and shapes written to one JSON file.
int write_bodies(const SceneArgs& a) {
  const std::string command = "bodies";
  if (a.scene.empty()) return usage_error("no scene file given", command);
  if (a.out.empty()) return usage_error("--out FILE.json is required to write the bodies", command);
  const std::string problem = file_problem(a.out, "the bodies file");
  if (!problem.empty()) return input_error(problem);
  try {
    const ratchet::SceneDef scene = ratchet::load_scene(a.scene, a.overrides);
    const ratchet::World world(scene);
    const fs::path parent = fs::path(a.out).parent_path();
    if (!parent.empty()) fs::create_directories(parent);
    ratchet::write_bodies_file(a.out, world.scene(), world.state());
    if (!a.quiet)
      std::cerr << "ratchet: " << scene.name << ": " << scene.bodies.size() << " bodies, " << scene.shapes.size()
                << " shapes -> " << a.out << "\n";
    return 0;
  } catch (const ratchet::SceneError& e) {
    std::cerr << "ratchet: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ratchet: error: " << e.what() << "\n";
    return 1;
  }
}

// --set key.path=value, as every scene command takes it.
void add_set_option(CLI::App* command, std::vector<std::string>& overrides) {
  command->add_option("--set", overrides, "override a scene field before checking; repeatable, applied in order")
      ->type_name("key.path=value")
      ->expected(1)  // one value per --set: the scene path after it stays a path
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

}  // namespace

int ratchet_cli_main(int argc, char** argv) {
  if (argc < 2) {
    std::cout << kUsage;
    return 2;
  }
  CLI::App app("ratchet: the NSCD reference engine", "ratchet");
  app.formatter(std::make_shared<Formatter>());
  app.footer("See docs/cli.md and docs/scene-format.md.");
  // Before the commands: they inherit the help flag.
  app.set_help_flag("-h,--help", "print this help and exit");
  app.set_version_flag("-V,--version", version_text(),
                       "print the version, build type, commit, source hash and compiler, and exit");
  app.require_subcommand(0, 1);
  app.allow_extras();  // unknown commands and options are reported below, in our words
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);  // as before: the last one counts

  CLI::App* help = app.add_subcommand("help", "print the usage, or the options of COMMAND");
  std::string help_topic;
  help->add_option("COMMAND", help_topic, "run, pack, bodies or sweep")->type_name("");
  CLI::App* version = app.add_subcommand("version", "print the version and build type");

  SceneArgs run_args, pack_args, bodies_args;
  CLI::App* run = app.add_subcommand("run", "Run a scene: DIR/timeseries.csv, DIR/bodies.csv, DIR/bodies_shapes.json, "
                                             "DIR/run.json and the outputs the scene asks for "
                                             "(docs/output-format.md).");
  run->add_option("SCENE.json", run_args.scene, "the scene file (docs/scene-format.md)")->type_name("");
  run->add_option("--out", run_args.out, "output folder, created if missing; required unless --explain")
      ->type_name("DIR");
  run->add_option("--packing", run_args.packing, "start from this settled packing (made by ratchet pack)")
      ->type_name("FILE");
  add_set_option(run, run_args.overrides);
  run->add_option("--resume", run_args.resume,
                  "continue the run in DIR from its checkpoint (after SIGINT, SIGTERM or a kill); nothing else given")
      ->type_name("DIR");
  run->add_flag("--explain", run_args.explain, "print the steps' phases and why, write nothing (--out is ignored)");
  run->add_flag("--quiet", run_args.quiet, "no progress line and no closing summary line");
  run->add_option("--progress-every", run_args.progress_every,
                  "when stderr is not a terminal (a batch job's log): a timestamped progress line this often "
                  "(default 60; 0: only at the end)")
      ->type_name("SECONDS")
      ->check(CLI::NonNegativeNumber);

  CLI::App* pack = app.add_subcommand("pack", "Pour and settle the bed to the end of the settle stage and write "
                                               "that state (a packing) to FILE.");
  pack->add_option("SCENE.json", pack_args.scene, "the scene file (it needs a thermal section)")->type_name("");
  pack->add_option("--out", pack_args.out,
                   "the packing file (required); its folder is created if missing; not a folder")
      ->type_name("FILE");
  add_set_option(pack, pack_args.overrides);
  pack->add_flag("--quiet", pack_args.quiet, "no progress line and no closing line");

  CLI::App* bodies = app.add_subcommand(
      "bodies", "Build the scene as run does (same generator, seed and --set overrides) and write its bodies and "
                "shapes to FILE.json: per body kind, radius or shape, pose, velocities, mass, principal inertia, "
                "bounding radius, fixed; per shape body-frame vertices, faces, volume (docs/output-format.md).");
  bodies->add_option("SCENE.json", bodies_args.scene, "the scene file (docs/scene-format.md)")->type_name("");
  bodies->add_option("--out", bodies_args.out,
                     "the JSON file (required), written atomically; its folder is created if missing; not a folder")
      ->type_name("FILE.json");
  add_set_option(bodies, bodies_args.overrides);
  bodies->add_flag("--quiet", bodies_args.quiet, "no closing line");

  std::string sweep_file, sweep_out, jobs_text, threads_text;
  std::vector<std::string> sweep_overrides;
  CLI::App* sweep_cmd = app.add_subcommand("sweep", "Run every point of a sweep (grid x realizations) from shared "
                                                    "packings; resumes: complete runs are kept (docs/sweeps.md).");
  sweep_cmd->add_option("SWEEP.json", sweep_file, "the sweep file")->type_name("");
  sweep_cmd->add_option("--out", sweep_out, "output folder (required); each run goes to DIR/runs/<id>/")
      ->type_name("DIR");
  // Read as text and checked below: CLI11 would name neither the option nor the rule.
  add_set_option(sweep_cmd, sweep_overrides);
  sweep_cmd->add_option("--jobs", jobs_text,
                        "runs at a time per process, N >= 1 (default: all cores; 1 per rank under mpirun)")
      ->type_name("N");
  sweep_cmd->add_option("--threads", threads_text,
                        "OpenMP threads of each run, T >= 1 (default 1); the results are the same bits for any T, "
                        "so one run can use the cores that jobs would leave idle")
      ->type_name("T");
  for (CLI::App* sub : {help, version, run, pack, bodies, sweep_cmd}) sub->allow_extras();

  const auto command_of = [&]() -> std::string {
    const auto subs = app.get_subcommands();
    return subs.empty() ? "" : subs.front()->get_name();
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    if (command_of().empty()) std::cout << kUsage;
    else std::cout << app.help();  // the help of the command given
    return 0;
  } catch (const CLI::CallForVersion&) {
    std::cout << version_text();
    return 0;
  } catch (const CLI::ParseError& e) {
    // "--out: 1 required DIR missing" is an option given without its value.
    const std::string what = e.what();
    if (e.get_name() == "ArgumentMismatch" && what.find(" required ") != std::string::npos &&
        what.size() > 8 && what.compare(what.size() - 8, 8, " missing") == 0)
      return usage_error(what.substr(0, what.find(':')) + " needs a value", command_of());
    return usage_error(what, command_of());
  }
  const std::string command = command_of();
  // Unknown arguments: the first one, as a command or as an option of the command.
  for (CLI::App* level : {static_cast<CLI::App*>(&app), command.empty() ? nullptr : app.get_subcommand(command)}) {
    const std::vector<std::string> extras = level == nullptr ? std::vector<std::string>() : level->remaining();
    if (extras.empty()) continue;
    const std::string& extra = extras.front();
    if (!extra.empty() && extra[0] == '-') return usage_error("unknown option '" + extra + "'", command);
    if (command.empty()) return usage_error("unknown command '" + extra + "'");
    if (command == "run" || command == "pack" || command == "bodies") {
      const SceneArgs& given = command == "run" ? run_args : command == "pack" ? pack_args : bodies_args;
      return usage_error("more than one scene file given ('" + given.scene + "', '" + extra + "')", command);
    }
    if (command == "sweep") return usage_error("more than one sweep file given", command);
    return usage_error("unexpected argument '" + extra + "'", command);
  }
  if (command.empty()) {  // no command and nothing left over: as with no arguments
    std::cout << kUsage;
    return 2;
  }
  if (command == "help") {
    if (help_topic.empty()) {
      std::cout << kUsage;
      return 0;
    }
    if (kSynopsis.count(help_topic) == 0)  // every command has a synopsis
      return usage_error("unknown command '" + help_topic + "'", "help");
    std::cout << app.get_subcommand(help_topic)->help();
    return 0;
  }
  if (command == "version") {
    std::cout << version_text();
    return 0;
  }
  if (command == "sweep") {
    if (sweep_file.empty() || sweep_out.empty()) return usage_error("sweep needs SWEEP.json and --out DIR", command);
    int jobs = 0;  // the default
    if (sweep_cmd->count("--jobs") > 0) {
      const std::optional<int> n = positive_int(jobs_text);
      if (!n) return usage_error("--jobs: expected a whole number >= 1 (runs at a time), got '" + jobs_text + "'", command);
      jobs = *n;
    }
    int threads = 1;
    if (sweep_cmd->count("--threads") > 0) {
      const std::optional<int> n = positive_int(threads_text);
      if (!n) return usage_error("--threads: expected a whole number >= 1 (threads per run), got '" + threads_text + "'",
                                 command);
      threads = *n;
    }
    const std::string problem = folder_problem(sweep_out);
    if (!problem.empty())
      return input_error("--out " + sweep_out + ": expected a folder, or a path where one can be created, but " +
                         problem);
    return sweep(sweep_file, sweep_out, jobs, threads, sweep_overrides, std::vector<std::string>(argv, argv + argc));
  }
  if (command == "bodies") return write_bodies(bodies_args);
  SceneArgs& args = command == "pack" ? pack_args : run_args;
  args.command_line.assign(argv, argv + argc);
  return run_or_pack(command == "pack", args);
}
