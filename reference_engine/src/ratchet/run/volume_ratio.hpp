// V/V0 over a run (docs/output-format.md, "Bed volume and V0"): the `V_over_V0`
// timeseries column, its values at the ends of heating and cooling of each cycle
// (cycles.csv) and at the end of the run (summary V_over_V0_end). Only with
// outputs.volume; the volume itself is observe/bed_volume.hpp.
#pragma once

#include <cmath>
#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/run/accumulator.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

class VolumeRatio final : public Accumulator {
 public:
  // V0 is the first state's volume until the settled bed's is taken.
  explicit VolumeRatio(const World& world);
  bool enabled() const { return enabled_; }
  double ratio(const World& world) const;  // V / V0 of the current state
  void after_step(const World& world, const ClockTick& tick) override;
  void timeseries_columns(std::vector<std::string>& names) const override;  // V_over_V0
  void timeseries_values(const World& world, std::vector<double>& values) const override;
  // V_over_V0_end_heating, V_over_V0_end_cooling
  void cycle_columns(std::vector<std::string>& names) const override;
  void cycle_cells(int cycle, std::vector<std::string>& cells) const override;
  // V/V0 at the end of heating / cooling of `cycle`; NaN if not recorded.
  double at_end_of_heating(int cycle) const { return at(v_heat_, cycle); }
  double at_end_of_cooling(int cycle) const { return at(v_cool_, cycle); }
  void summarize(const World& world, nlohmann::json& summary) const;
  void finish(const RunEnd& end, nlohmann::json& summary) const override;  // summarize
  nlohmann::json save() const override;
  void restore(const nlohmann::json& j) override;

 private:
  static double at(const std::vector<double>& v, int cycle) {
    return cycle >= 0 && static_cast<std::size_t>(cycle) < v.size() ? v[static_cast<std::size_t>(cycle)] : NAN;
  }
  bool enabled_ = false;
  double v0_ = NAN;
  std::vector<double> v_heat_, v_cool_;  // per cycle
};

}  // namespace ratchet
