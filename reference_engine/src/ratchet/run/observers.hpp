// The observables a scene asks for (design.md s. 5), gathered during a run from the
// pure functions in observe/: per-cycle peak pressure and V/V0, the mean peak pressure
// P_max over the steady cycles, snapshots of the centres at cycle ends and the
// displacement / vorticity fields between them, wall stress profiles, VTK files.
// Nothing is computed that the scene's `outputs` does not ask for.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/world/world.hpp"

namespace ratchet {

class RunObservers {
 public:
  RunObservers(const World& world, std::string out_dir);

  // Extra timeseries columns, in this order (names, then values for the current state).
  const std::vector<std::string>& extra_columns() const { return columns_; }
  void extra_values(const World& world, std::vector<double>& values) const;

  // After every step: peaks, stage ends, snapshots, VTK, profiles.
  void after_step(const World& world);

  // End of the run: writes cycles.csv, displacement_<a>_<b>.csv, wall_profile.csv and
  // returns the summary (P_max, V/V0, W_rms per window) for run.json.
  nlohmann::json finish(const World& world);

  // Particle points whose convex hull is the bed: polyhedron vertices; for spheres the
  // 6 axis points and 8 diagonal points of the surface (an inscribed approximation).
  static std::vector<Vec3> bed_points(const World& world);
  static double bed_volume(const World& world);

 private:
  struct CycleRecord {
    int cycle = 0;
    double peak_pressure = 0.0, t_peak = 0.0;
    double v_heat = NAN, v_cool = NAN;  // V/V0 at the end of heating / cooling
    double contacts_sum = 0.0, iterations_sum = 0.0;
    long long steps = 0, unconverged = 0;
  };
  // Stage boundaries crossed by the step from t_prev to t (several at once when a hold
  // has zero length).
  struct StageEnds {
    bool heating = false, cooling = false, cycle = false;
  };
  StageEnds stage_ends(double t_prev, double t) const;
  void write_vtk(const World& world, const std::string& tag) const;
  void begin_wall_profile(const World& world);
  void accumulate_wall_profile(const World& world);
  void flush_wall_profile(const World& world, int cycle);

  const SceneDef& scene_;
  std::string out_dir_;
  std::vector<std::string> columns_;
  bool thermal_ = false;
  bool started_ = false;  // the start of cycling (V0, snapshot 0) has been taken
  bool settle_pending_ = false;  // a settle section's stage has not ended yet (V0 is taken when it does)
  double v0_ = NAN;
  double t_prev_ = 0.0;
  std::vector<CycleRecord> cycles_;
  std::vector<std::vector<Vec3>> snapshots_;  // centres at the start of cycling and each cycle end
  std::vector<std::string> profile_rows_;
  // Wall stress profile: normal impulse per height bin summed over the cold hold.
  std::vector<double> profile_impulse_;
  double profile_time_ = 0.0, profile_height_ = 0.0;
  bool in_cold_hold_ = false;
  bool in_settled_window_ = false;  // outputs.settled_profile_time: the window before cycling
  // Block average of P(t) over outputs.pressure_window for the per-cycle peaks: NSCD
  // wall impulses are intermittent, so single-step values are noisy.
  double block_sum_ = 0.0, block_time_ = 0.0, block_start_ = 0.0;
  int block_cycle_ = -1;
};

}  // namespace ratchet
