// The files of one run (docs/output-format.md): timeseries.csv, bodies.csv, run.json.
// CSVs are written as they grow under ".partial" names and renamed at the end; run.json
// is written last, so its presence with "status": "completed" marks a finished run.
// The observers' optional columns come in as names and values (run/observers.hpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/io/atomic_file.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

class RunOutput {
 public:
  // Creates `dir` and writes the CSV headers (the runner has removed an earlier run's
  // outputs first, remove_previous_outputs, before any observer wrote); extra_columns
  // follow the fixed timeseries columns. Rows are written by the caller, step 0 included.
  RunOutput(const std::string& dir, const std::vector<std::string>& extra_columns);
  // A resumed run: the CSVs' .partial files cut back to the byte lengths a checkpoint
  // recorded (flush_sizes) and appended to.
  static std::unique_ptr<RunOutput> resume(const std::string& dir, const nlohmann::json& sizes);
  // One timeseries row; `extra` holds one value per extra column, in their order.
  void write_timeseries_row(const World& world, const std::vector<double>& extra);
  void write_bodies(const World& world);
  // Renames the CSVs into place and writes run.json with the given summary.
  void finish(const World& world, const nlohmann::json& summary);
  // Flushes the CSVs and returns their byte lengths, {"timeseries.csv": n, "bodies.csv": n}.
  nlohmann::json flush_sizes();
  // A stopped run: the CSVs stay as .partial files for --resume, run.json gets `summary`.
  void interrupt(const World& world, const nlohmann::json& summary);

 private:
  explicit RunOutput(std::string dir) : dir_(std::move(dir)) {}
  void write_run_json(const World& world, const nlohmann::json& summary) const;
  std::string dir_;
  std::unique_ptr<AtomicFile> timeseries_, bodies_;
};

// Removes from `dir` what an earlier run wrote there: run.json first (the folder no longer
// looks complete), then timeseries.csv, bodies.csv, bodies_shapes.json, cycles.csv, wall_profile.csv,
// displacement_<a>_<b>.csv, checkpoint.state (and their .partial files), and in vtk/ the snapshots
// particles_*, contacts_*, container_* (.vtp, or .vtk of older versions) and the .pvd
// indexes. Other files are left alone. Returns the paths removed.
std::vector<std::string> remove_previous_outputs(const std::string& dir);

// The engine that wrote a file: {name, version, build_type, commit, source_hash}
// (core/build_info.hpp). Sweeps reuse a run or a packing only when it matches.
nlohmann::json engine_record();

// Empty when `recorded` (a file's "engine" object) is this engine: the same version
// and source hash (the hash covers the sources, the build type and the compiler, and
// is the same for every commit that leaves the engine alone). Otherwise why not, e.g.
// "made by engine 0.1.0 source 1a2b..., this is 0.1.0 source 3c4d...".
std::string other_engine(const nlohmann::json& recorded);

// Run metadata: engine, scene as run and with its defaults filled in, hash, effects,
// plan, timings.
nlohmann::json run_metadata(const World& world);

// 17 significant digits (%.17g): always reads back to the same double.
std::string format_double(double x);

}  // namespace ratchet
