// The files of one run (docs/output-format.md): timeseries.csv, bodies.csv, run.json.
// CSVs are written as they grow under ".partial" names and renamed at the end; run.json
// is written last, so its presence with "status": "completed" marks a finished run.
#pragma once

#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "ratchet/io/atomic_file.hpp"
#include "ratchet/run/observers.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

class RunOutput {
 public:
  RunOutput(const std::string& dir, const World& world, const RunObservers& observers);
  void write_timeseries_row(const World& world);
  void write_bodies(const World& world);
  // Renames the CSVs into place and writes run.json with the given summary.
  void finish(const World& world, const nlohmann::json& summary);

 private:
  std::string dir_;
  const RunObservers& observers_;
  std::unique_ptr<AtomicFile> timeseries_, bodies_;
  mutable std::vector<double> extra_;
};

// Run metadata: scene as run, hash, engine version, effects, plan, timings.
nlohmann::json run_metadata(const World& world);

// 17 significant digits (%.17g): always reads back to the same double.
std::string format_double(double x);

}  // namespace ratchet
