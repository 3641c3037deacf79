#include "ratchet/run/runner.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "ratchet/io/bodies_file.hpp"
#include "ratchet/observe/energy.hpp"
#include "ratchet/run/observers.hpp"
#include "ratchet/run/checkpoint.hpp"
#include "ratchet/run/packing.hpp"
#include "ratchet/run/provenance.hpp"
#include "ratchet/run/run_output.hpp"
#include "ratchet/run/run_warnings.hpp"
#include "ratchet/run/state_bounds.hpp"
#include "ratchet/run/stop_request.hpp"

namespace ratchet {

namespace {

// Seconds between redraws of the progress line on a terminal: often enough to look live,
// rarely enough to cost nothing (a log file gets a line every RunOptions::log_every).
constexpr double kTtyRedraw = 0.5;

std::string format_seconds(double s) {
  char buf[32];
  if (s >= 3600) std::snprintf(buf, sizeof buf, "%dh%02dm", static_cast<int>(s / 3600), static_cast<int>(s / 60) % 60);
  else if (s >= 60) std::snprintf(buf, sizeof buf, "%dm%02ds", static_cast<int>(s / 60), static_cast<int>(s) % 60);
  else std::snprintf(buf, sizeof buf, "%.0fs", s);
  return buf;
}

}  // namespace

std::string utc_stamp() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return buf;
}

std::string progress_line(const std::string& text, int columns) {
  if (columns <= 0) return "\r" + text + "   ";  // not a terminal: as it always was
  // The last column stays free: some terminals wrap as soon as it is written, and a
  // wrapped line cannot be rewritten with \r. Cut at a UTF-8 character boundary.
  const std::size_t room = columns > 1 ? static_cast<std::size_t>(columns - 1) : 1;
  std::size_t end = 0, chars = 0;
  for (; end < text.size(); ++end) {
    if ((static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) continue;  // inside a character
    if (chars == room) break;
    ++chars;
  }
  return "\r" + text.substr(0, end) + "\x1b[K";  // clear what a longer line left
}

int terminal_columns(int fd) {
  winsize ws{};
  if (ioctl(fd, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0) return ws.ws_col;
  if (const char* env = std::getenv("COLUMNS")) {
    char* end = nullptr;
    const long n = std::strtol(env, &end, 10);
    if (end != env && *end == '\0' && n > 0 && n <= 100000) return static_cast<int>(n);
  }
  return 80;
}

namespace {

// What the runner keeps besides the world and observers, for a checkpoint.
nlohmann::json run_record(const nlohmann::json& provenance, const nlohmann::json& packing,
                          const nlohmann::json& packing_settle, const RunWarnings& warnings,
                          const SettleMonitor* settle, const RunObservers& observers, RunOutput& out) {
  return {{"provenance", provenance},
          {"packing", packing},
          {"packing_settle", packing_settle},
          {"warnings", warnings.save()},
          {"settle_monitor", settle ? settle->save() : nlohmann::json(nullptr)},
          {"observers", observers.save()},
          {"files", out.flush_sizes()}};
}

}  // namespace

RunResult run_world(World& world, const RunOptions& options, const std::function<void(const World&)>& each_step) {
  const SceneDef& scene = world.scene();  // its end and start_time move when a settle section's stage ends
  const bool resuming = !options.resume.is_null();
  if (resuming && options.out_dir.empty()) throw std::invalid_argument("run_world: resuming needs the run's folder");
  if (!options.out_dir.empty()) {
    std::filesystem::create_directories(options.out_dir);
    if (resuming) {
      // The interrupted run's run.json goes first: the folder is not finished.
      std::filesystem::remove(options.out_dir + "/run.json");
    } else {
      // An earlier run's outputs go before any observer writes (a VTK snapshot of the
      // first state, for one): old files never stand beside this run's.
      remove_previous_outputs(options.out_dir);
      // The bodies and their shapes as the run starts: the folder is self-contained
      // (docs/output-format.md, "Bodies and shapes").
      write_bodies_file(options.out_dir + "/" + kBodiesFileName, world.scene(), world.state());
    }
  }
  const nlohmann::json& saved = options.resume;
  // The packing the run started from (null: none), as the interrupted run had it.
  const nlohmann::json packing = resuming ? saved.at("packing") : options.packing;
  const nlohmann::json packing_settle = resuming ? saved.at("packing_settle") : options.packing_settle;
  const nlohmann::json invocation = invocation_record(options.command_line);
  const nlohmann::json provenance =
      resuming ? resumed_provenance(saved.value("provenance", nlohmann::json()), invocation) : invocation;
  RunObservers observers = resuming ? RunObservers(world, options.out_dir, saved.at("observers"))
                                    : RunObservers(world, options.out_dir);
  RunWarnings warnings = resuming ? RunWarnings(saved.at("warnings")) : RunWarnings();
  if (const std::string squeeze = squeeze_warning(scene); !resuming && !squeeze.empty())
    std::fprintf(stderr, "%s: warning: %s\n", scene.source.c_str(), squeeze.c_str());
  // A run from a packing starts after its settle stage and reports the packing's record.
  std::optional<SettleMonitor> settle;
  if (resuming) {
    if (!saved.at("settle_monitor").is_null()) settle.emplace(world, saved.at("settle_monitor"));
  } else if (packing.is_null()) {
    settle.emplace(world);
  }
  std::unique_ptr<RunOutput> out;
  std::vector<double> extra;  // the observers' columns of a timeseries row
  auto write_row = [&]() {
    observers.extra_values(world, extra);
    out->write_timeseries_row(world, extra);
  };
  if (!options.out_dir.empty()) {
    if (resuming) {
      out = RunOutput::resume(options.out_dir, saved.at("files"));
    } else {
      out = std::make_unique<RunOutput>(options.out_dir, observers.extra_columns());
      write_row();
      out->write_bodies(world);
    }
  }
  const auto start = std::chrono::steady_clock::now();
  auto last_print = start;
  const std::int64_t first_step = world.state().step;
  const bool tty = options.progress && isatty(STDERR_FILENO) == 1;
  const int every_ts = scene.outputs.timeseries_every;
  const int every_bodies = scene.outputs.bodies_every;
  const int every_checkpoint = scene.outputs.checkpoint_every;
  bool printed = false;  // a progress line is on the terminal: an error must start a new line
  auto seconds_since_start = [&]() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  try {
    while (world.state().step < scene.steps) {
      const double s_c_before = world.state().s_c;
      world.step();
      const std::int64_t k = world.state().step;
      const double ke = kinetic_energy(world.scene(), world.state());
      if (!std::isfinite(ke))
        throw RunError(scene.source + ": the state became non-finite at step " + std::to_string(k) +
                       " (t = " + std::to_string(world.state().t) + "); the time step may be too large");
      if (const std::string wrong = unphysical_state(world); !wrong.empty())
        throw RunError(scene.source + ": the state became unphysical at step " + std::to_string(k) +
                       " (t = " + std::to_string(world.state().t) + "): " + wrong +
                       "; the time step may be too large for the speeds, or the bed is jammed beyond what the "
                       "contact law can hold");
      // The cap is meant to be out of reach (docs/method.md s. 7): a step that stops there
      // is reported at once, and the run's count and first such step go to run.json.
      if (warnings.after_step(world, s_c_before)) {
        std::fprintf(stderr, "%s%s: warning: step %lld (t = %.6g) stopped at solver.max_iterations = %d sweeps "
                             "unconverged (residual %.3g, tolerance %.3g); further such steps are counted in run.json\n",
                     printed ? "\n" : "", scene.source.c_str(), static_cast<long long>(k), world.state().t,
                     scene.solver.max_iterations, world.stats().residual, scene.solver.tolerance);
        printed = false;
      }
      // Before the observers: the state that ends the settle stage starts the cycling.
      if (settle) settle->after_step(world);
      observers.after_step(world);
      const std::int64_t total = scene.steps;
      if (out) {
        if (k % every_ts == 0 || k == total) write_row();
        if ((every_bodies > 0 && k % every_bodies == 0) || k == total) out->write_bodies(world);
      }
      if (each_step) each_step(world);
      // A checkpoint after everything this step writes; a stop request is honoured here,
      // between steps, where the checkpoint is whole.
      if (const int sig = stop_signal(); sig != 0 && k < total) {
        if (printed) std::fprintf(stderr, "\n");
        const std::string what = scene.source + ": stopped by " + signal_name(sig) + " after step " +
                                 std::to_string(k) + " of " + std::to_string(total);
        if (out) {
          write_checkpoint(options.out_dir, world, run_record(provenance, packing, packing_settle, warnings, settle ? &*settle : nullptr, observers, *out));
          out->interrupt(world, {{"status", "interrupted"},
                                 {"error", what},
                                 {"signal", signal_name(sig)},
                                 {"checkpoint", kCheckpointFileName},
                                 {"resume", "ratchet run --resume " + options.out_dir},
                                 {"wall_seconds", seconds_since_start()},
                                 {"packing", packing}, {"provenance", provenance}});
        }
        throw RunInterrupted(what, sig);
      }
      if (out && every_checkpoint > 0 && k % every_checkpoint == 0 && k < total)
        write_checkpoint(options.out_dir, world, run_record(provenance, packing, packing_settle, warnings, settle ? &*settle : nullptr, observers, *out));
      if (options.progress) {
        const auto now = std::chrono::steady_clock::now();
        const double since = std::chrono::duration<double>(now - last_print).count();
        const bool due = k == total || (tty ? since > kTtyRedraw : options.log_every > 0.0 && since >= options.log_every);
        if (due) {
          last_print = now;
          const double el = std::chrono::duration<double>(now - start).count();
          const double left = el / static_cast<double>(k - first_step) * static_cast<double>(total - k);
          // The time left first: a narrow terminal cuts the end of the line.
          char tail[256];
          std::snprintf(tail, sizeof tail, ": %s left, step %lld/%lld%s (%.1f%%) t=%.4g T=%.4g contacts=%d iter=%d",
                        format_seconds(left).c_str(), static_cast<long long>(k), static_cast<long long>(total),
                        world.settling() ? " at most, settling" : "",
                        100.0 * static_cast<double>(k) / static_cast<double>(total), world.state().t, world.state().T,
                        world.stats().contacts, world.stats().iterations);
          if (tty) {
            // The width is read at each print: the terminal may have been resized.
            std::fputs(progress_line(scene.name + tail, terminal_columns(STDERR_FILENO)).c_str(), stderr);
            printed = k != total;
            if (k == total) std::fprintf(stderr, "\n");
          } else {
            std::fprintf(stderr, "%s %s%s\n", utc_stamp().c_str(), scene.name.c_str(), tail);
          }
          std::fflush(stderr);
        }
      }
    }
  } catch (const RunError& e) {
    if (printed) std::fprintf(stderr, "\n");
    // Keep what was written, marked failed: the CSVs up to here and a run.json that says
    // why (docs/output-format.md, "When a run fails").
    if (out) {
      out->finish(world, {{"status", "failed"}, {"error", e.what()}, {"wall_seconds", seconds_since_start()},
                          {"packing", packing}, {"provenance", provenance}, {"warnings", warnings.sentences(world)}});
      std::filesystem::remove(options.out_dir + "/" + kCheckpointFileName);  // it would only fail again
    }
    throw;
  } catch (const RunInterrupted&) {
    throw;
  } catch (...) {
    if (printed) std::fprintf(stderr, "\n");
    throw;
  }
  RunResult r;
  r.steps = world.state().step;
  r.wall_seconds = seconds_since_start();
  r.summary = observers.finish(world);
  if (settle) r.settle = has_settle_stage(scene) ? settle->record() : nlohmann::json(nullptr);
  else r.settle = packing_settle;
  r.warnings = warnings.sentences(world);
  for (const auto& w : r.warnings)
    if (w.get<std::string>().rfind("in ", 0) == 0)  // the travel warnings; the cap was reported at its first step
      std::fprintf(stderr, "%s: warning: %s\n", scene.source.c_str(), w.get<std::string>().c_str());
  if (out) {
    out->finish(world, {{"status", "completed"}, {"wall_seconds", r.wall_seconds}, {"summary", r.summary},
                        {"settle", r.settle}, {"packing", packing}, {"provenance", provenance}, {"warnings", r.warnings}});
    std::filesystem::remove(options.out_dir + "/" + kCheckpointFileName);  // the run is whole without it
  }
  return r;
}

}  // namespace ratchet
