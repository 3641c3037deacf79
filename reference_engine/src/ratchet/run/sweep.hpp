// Sweeps: a base scene, a grid over scene fields by dotted path, and realizations
// (seeds). Each run is an ordinary run in DIR/runs/<id>/; the summary is built from
// the runs' run.json files only, so it is the same whoever ran them (threads, MPI
// ranks, or an earlier, interrupted invocation).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/run/checkpoint.hpp"
#include "ratchet/scene/scene.hpp"

namespace ratchet {

struct SweepRun {
  int id = 0;
  std::vector<std::pair<std::string, nlohmann::json>> params;  // grid values, in grid order
  std::uint64_t seed = 1;
  nlohmann::json scene;  // the base scene with params, seed and `set` applied
  std::string packing_key;  // run/packing.hpp; empty: the run starts from its scene
};

// A settled packing shared by the runs with the same packing key.
struct SweepPacking {
  std::string key;
  std::vector<int> runs;  // ids of the runs that start from it, ascending; the first one's scene makes it
};

struct SweepPlan {
  std::string source;  // the sweep file
  std::string out_dir;
  std::vector<std::string> grid_keys;
  std::vector<SweepRun> runs;
  std::vector<SweepPacking> packings;  // in the order of their first run
  std::vector<std::string> command_line;  // of the program that runs it (the runs' run.json provenance); may be empty
};

// Reads a sweep file and checks every run's scene (errors name the sweep file, the
// run and the field) before anything is written.
// `overrides` (`ratchet sweep --set key.path=value`, applied in order after the file's
// `set`) change the base scene of every run.
SweepPlan load_sweep(const std::string& path, const std::string& out_dir,
                     const std::vector<std::string>& overrides = {});

std::string run_dir(const SweepPlan& plan, int id);

// The checkpoint an interrupted run of this scene left in `dir` (run/checkpoint.hpp), if
// it can go on from it; none when there is none, or when it is damaged, of another
// engine or of another scene: the run then starts over, and *why_not (if given) says
// why (empty when there was no checkpoint at all).
std::optional<ResumePoint> resumable_checkpoint(const std::string& dir, const SceneDef& scene,
                                                std::string* why_not = nullptr);

// True if DIR/runs/<id>/run.json says completed for this run's scene hash.
bool run_completed(const SweepPlan& plan, const SweepRun& run);

// DIR/packings/<key>.state
std::string packing_path(const SweepPlan& plan, const std::string& key);

// True if the packing file exists, reads back whole and has this key.
bool packing_ready(const SweepPlan& plan, const SweepPacking& packing);

// Indices into plan.packings of the packings that some run not yet completed needs.
std::vector<int> needed_packings(const SweepPlan& plan);

// Makes the given packings (indices into plan.packings) on `jobs` threads, each pour on
// `threads_per_run` OpenMP threads, skipping those already made; a half-written one
// (only a .partial file) is made again.
void make_packings(const SweepPlan& plan, const std::vector<int>& indices, int jobs,
                   const std::function<void(const std::string&)>& progress, int threads_per_run = 1);

// Runs the given run ids on `jobs` threads (each run on `threads_per_run` OpenMP threads:
// the same bits for any count), skipping completed ones. A run with a packing key starts
// from its packing, which must have been made (make_packings) before. `progress` is
// called after each run with a line to show.
void run_sweep(const SweepPlan& plan, const std::vector<int>& ids, int jobs,
               const std::function<void(const std::string&)>& progress, int threads_per_run = 1);

// Writes DIR/summary.csv (deterministic: no timings) and DIR/timings.csv from the
// run.json files. Runs without a completed run.json get status "missing".
void write_sweep_summary(const SweepPlan& plan);

// One cell of summary.csv: a number as the run files write it, a boolean as true/false,
// null as empty, a string or any other JSON value (an array or object a grid swept) as
// itself, quoted (RFC 4180) when it holds a comma, a quote or a line break.
std::string summary_csv_cell(const nlohmann::json& v);

}  // namespace ratchet
