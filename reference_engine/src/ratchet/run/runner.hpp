// Runs a scene to its end, writing the run's files (run/run_output.hpp), with an
// optional progress line. Used by `ratchet run` and by the tests.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/world/world.hpp"

namespace ratchet {

struct RunOptions {
  std::string out_dir;        // empty: no files
  bool progress = false;      // progress with the time left, on stderr (docs/cli.md, "Progress line")
  // Off a terminal (a batch job's log): a timestamped line this often, in seconds, and at
  // the last step; on a terminal the line is rewritten every 0.5 s instead.
  double log_every = 60.0;
  // Set when the world's state was loaded from a packing (run/packing.hpp):
  // packing_reference(...) and the settle record stored in the packing. Both go to
  // run.json; null: the run starts from the scene and records its own settle stage.
  nlohmann::json packing;
  nlohmann::json packing_settle;
  // Set when the run continues from a checkpoint (run/checkpoint.hpp): the checkpoint's
  // run record (ResumePoint::run), the world already at its state (resume_world). The
  // run then goes on in out_dir exactly as if it had never stopped. Null: a fresh run.
  nlohmann::json resume;
  // The program's arguments, argv[0] first (run.json provenance, run/provenance.hpp);
  // empty for a run started from code.
  std::vector<std::string> command_line;
};

struct RunResult {
  std::int64_t steps = 0;
  double wall_seconds = 0.0;
  nlohmann::json summary;  // the observers' summary (P_max, V/V0, W_rms ...), also in run.json
  nlohmann::json settle;   // the settle record (run/packing.hpp), null without a thermal section
  nlohmann::json warnings = nlohmann::json::array();  // what the run found wrong but survived, also in run.json
};

// Thrown when the state stops being finite (divergence).
struct RunError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The progress line as written to stderr (docs/cli.md, "Progress line"). On a terminal
// of `columns` columns: "\r", `text` cut to columns - 1 characters and "\x1b[K" (clear
// to the end of the line), so a shorter line leaves nothing behind and a long one does
// not wrap. Not a terminal (columns <= 0): "\r", `text` and three spaces.
std::string progress_line(const std::string& text, int columns);

// The UTC time as 2026-11-26T02:58:01Z, the stamp of the progress lines off a terminal.
std::string utc_stamp();

// Width of the terminal on `fd`: TIOCGWINSZ, else $COLUMNS, else 80.
int terminal_columns(int fd);

// Runs world until scene().steps steps are done. Calls `each_step` (if given) after
// every step, e.g. for tests that watch the trajectory. Writes a checkpoint every
// outputs.checkpoint_every steps; on a stop request (run/stop_request.hpp) writes one,
// marks run.json interrupted and throws RunInterrupted. Throws RunError (run.json
// marked failed) when the state diverges or turns unphysical.
RunResult run_world(World& world, const RunOptions& options,
                    const std::function<void(const World&)>& each_step = {});

}  // namespace ratchet
