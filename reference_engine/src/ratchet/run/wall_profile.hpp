// Time-averaged side-wall stress per height band (docs/output-format.md,
// `wall_profile.csv`): over the cold hold of every cycle (outputs.wall_profile_bins),
// and over the settled bed's window before cycling (outputs.settled_profile_time,
// cycle -1). The bands of one average are fixed by the bed height at its first state;
// the per-step profile is observe/wall_pressure.hpp, wall_stress_profile.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/run/accumulator.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

class WallProfile final : public Accumulator {
 public:
  explicit WallProfile(const SceneDef& scene) : scene_(scene) {}
  void after_step(const World& world, const ClockTick& tick) override;
  // Writes DIR/wall_profile.csv (header and the rows so far).
  void write(const std::string& out_dir) const;
  void finish(const RunEnd& end, nlohmann::json& summary) const override;  // write, when asked for
  nlohmann::json save() const override;
  void restore(const nlohmann::json& j) override;

 private:
  void begin(const World& world);
  void accumulate(const World& world);
  void flush(const World& world, int cycle);

  const SceneDef& scene_;
  std::vector<std::string> rows_;
  std::vector<double> impulse_;  // stress x time per band, summed over the current average
  double time_ = 0.0, height_ = 0.0;
  bool in_cold_hold_ = false;
  bool in_settled_window_ = false;
  std::vector<double> z_, force_;  // the step's side-wall contacts (storage reused)
};

}  // namespace ratchet
