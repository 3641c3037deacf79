#include "ratchet/run/runner.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "ratchet/geometry/particle_generator.hpp"
#include "ratchet/io/bodies_file.hpp"
#include "ratchet/observe/energy.hpp"
#include "ratchet/run/observers.hpp"
#include "ratchet/run/packing.hpp"
#include "ratchet/run/run_output.hpp"
#include "ratchet/run/state_bounds.hpp"

namespace ratchet {

namespace {

std::string format_seconds(double s) {
  char buf[32];
  if (s >= 3600) std::snprintf(buf, sizeof buf, "%dh%02dm", static_cast<int>(s / 3600), static_cast<int>(s / 60) % 60);
  else if (s >= 60) std::snprintf(buf, sizeof buf, "%dm%02ds", static_cast<int>(s / 60), static_cast<int>(s) % 60);
  else std::snprintf(buf, sizeof buf, "%.0fs", s);
  return buf;
}

// The largest speed of a free body (centre of mass).
double max_speed(const World& world) {
  double v2 = 0.0;
  const auto& bodies = world.scene().bodies;
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (!bodies[i].fixed) v2 = std::max(v2, world.state().v[i].squaredNorm());
  return std::sqrt(v2);
}

}  // namespace

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

RunResult run_world(World& world, const RunOptions& options, const std::function<void(const World&)>& each_step) {
  const SceneDef& scene = world.scene();  // its end and start_time move when a settle section's stage ends
  // An earlier run's outputs go before any observer writes (a VTK snapshot of the first
  // state, for one): old files never stand beside this run's.
  if (!options.out_dir.empty()) {
    std::filesystem::create_directories(options.out_dir);
    remove_previous_outputs(options.out_dir);
    // The bodies and their shapes as the run starts: the folder is self-contained
    // (docs/output-format.md, "Bodies and shapes").
    write_bodies_file(options.out_dir + "/" + kBodiesFileName, world.scene(), world.state());
  }
  RunObservers observers(world, options.out_dir);
  std::unique_ptr<RunOutput> out;
  std::vector<double> extra;  // the observers' columns of a timeseries row
  auto write_row = [&]() {
    observers.extra_values(world, extra);
    out->write_timeseries_row(world, extra);
  };
  if (!options.out_dir.empty()) {
    out = std::make_unique<RunOutput>(options.out_dir, observers.extra_columns());
    write_row();
    out->write_bodies(world);
  }
  const auto start = std::chrono::steady_clock::now();
  auto last_print = start;
  const bool tty = options.progress && isatty(STDERR_FILENO) == 1;
  const int every_ts = scene.outputs.timeseries_every;
  const int every_bodies = scene.outputs.bodies_every;
  // A run from a packing starts after its settle stage and reports the packing's record.
  std::optional<SettleMonitor> settle;
  if (options.packing.is_null()) settle.emplace(world);
  bool printed = false;  // a progress line is on the terminal: an error must start a new line
  // The cap is meant to be out of reach (docs/method.md s. 7): a step that stops there
  // is reported at once, and the run's count and first such step go to run.json.
  std::int64_t first_capped = -1;
  double first_capped_t = 0.0, first_capped_residual = 0.0;
  // A body that moves more than the contact margin in one step can meet a contact only
  // after it has overlapped (docs/scene-format.md, solver.contact_margin): flagged.
  std::int64_t first_fast = -1, fast_steps = 0;
  double fastest_travel = 0.0;
  try {
    while (world.state().step < scene.steps) {
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
      if (!world.stats().converged && first_capped < 0) {
        first_capped = k;
        first_capped_t = world.state().t;
        first_capped_residual = world.stats().residual;
        std::fprintf(stderr, "%s%s: warning: step %lld (t = %.6g) stopped at solver.max_iterations = %d sweeps "
                             "unconverged (residual %.3g, tolerance %.3g); further such steps are counted in run.json\n",
                     printed ? "\n" : "", scene.source.c_str(), static_cast<long long>(k), world.state().t,
                     scene.solver.max_iterations, world.stats().residual, scene.solver.tolerance);
        printed = false;
      }
      const double travel = max_speed(world) * scene.dt;
      if (travel > scene.solver.contact_margin) {
        if (first_fast < 0) first_fast = k;
        ++fast_steps;
        fastest_travel = std::max(fastest_travel, travel);
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
      if (options.progress) {
        const auto now = std::chrono::steady_clock::now();
        if (std::chrono::duration<double>(now - last_print).count() > 0.5 || k == total) {
          last_print = now;
          const double el = std::chrono::duration<double>(now - start).count();
          const double left = el / static_cast<double>(k) * static_cast<double>(total - k);
          char tail[256];
          std::snprintf(tail, sizeof tail, ": step %lld/%lld%s (%.1f%%) t=%.4g T=%.4g contacts=%d iter=%d  %s left",
                        static_cast<long long>(k), static_cast<long long>(total),
                        world.settling() ? " at most, settling" : "",
                        100.0 * static_cast<double>(k) / static_cast<double>(total), world.state().t, world.state().T,
                        world.stats().contacts, world.stats().iterations, format_seconds(left).c_str());
          // The width is read at each print: the terminal may have been resized.
          std::fputs(progress_line(scene.name + tail, tty ? terminal_columns(STDERR_FILENO) : 0).c_str(), stderr);
          printed = k != total;
          if (k == total) std::fprintf(stderr, "\n");
          std::fflush(stderr);
        }
      }
    }
  } catch (const RunError& e) {
    if (printed) std::fprintf(stderr, "\n");
    // Keep what was written, marked failed: the CSVs up to here and a run.json that says
    // why (docs/output-format.md, "When a run fails").
    if (out)
      out->finish(world, {{"status", "failed"}, {"error", e.what()},
                          {"wall_seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()},
                          {"packing", options.packing}});
    throw;
  } catch (...) {
    if (printed) std::fprintf(stderr, "\n");
    throw;
  }
  RunResult r;
  r.steps = world.state().step;
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.summary = observers.finish(world);
  if (settle) r.settle = has_settle_stage(scene) ? settle->record() : nlohmann::json(nullptr);
  else r.settle = options.packing_settle;
  if (first_capped >= 0) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "%lld of %lld steps stopped at solver.max_iterations = %d sweeps unconverged, the first at step %lld "
                  "(t = %.6g, residual %.3g against the tolerance %.3g)",
                  static_cast<long long>(world.stats().unconverged_steps), static_cast<long long>(r.steps),
                  scene.solver.max_iterations, static_cast<long long>(first_capped), first_capped_t,
                  first_capped_residual, scene.solver.tolerance);
    r.warnings.push_back(text);
  }
  if (scene.redrawn_particles > 0) {
    const std::string text = std::to_string(scene.redrawn_particles) +
                             " generated particle(s) were slivers (inradius below " + std::to_string(kMinInradius) +
                             " of their radius) and were drawn again: particles.generate.vertices is low";
    r.warnings.push_back(text);
  }
  if (first_fast >= 0) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "in %lld of %lld steps a body moved farther than solver.contact_margin = %.3g per step (at most "
                  "%.3g, the first at step %lld): contacts may be found only after they overlap; a smaller "
                  "time.dt or a larger margin avoids it",
                  static_cast<long long>(fast_steps), static_cast<long long>(r.steps), scene.solver.contact_margin,
                  fastest_travel, static_cast<long long>(first_fast));
    r.warnings.push_back(text);
    std::fprintf(stderr, "%s: warning: %s\n", scene.source.c_str(), text);
  }
  if (out)
    out->finish(world, {{"status", "completed"}, {"wall_seconds", r.wall_seconds}, {"summary", r.summary},
                        {"settle", r.settle}, {"packing", options.packing}, {"warnings", r.warnings}});
  return r;
}

}  // namespace ratchet
