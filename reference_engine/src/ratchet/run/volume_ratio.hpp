// V/V0 over a run (docs/output-format.md, "Bed volume and V0"): the `V_over_V0`
// timeseries column, its values at the ends of heating and cooling of each cycle
// (cycles.csv) and at the end of the run (summary V_over_V0_end). Only with
// outputs.volume; the volume itself is observe/bed_volume.hpp.
#pragma once

#include <cmath>
#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/run/cycle_clock.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

class VolumeRatio {
 public:
  // V0 is the first state's volume until the settled bed's is taken.
  explicit VolumeRatio(const World& world);
  bool enabled() const { return enabled_; }
  double ratio(const World& world) const;  // V / V0 of the current state
  void after_step(const World& world, const ClockTick& tick);
  // V/V0 at the end of heating / cooling of `cycle`; NaN if not recorded.
  double at_end_of_heating(int cycle) const { return at(v_heat_, cycle); }
  double at_end_of_cooling(int cycle) const { return at(v_cool_, cycle); }
  void summarize(const World& world, nlohmann::json& summary) const;
  // A checkpoint's record of this accumulator (run/checkpoint.hpp), and its restore.
  nlohmann::json save() const;
  void restore(const nlohmann::json& j);

 private:
  static double at(const std::vector<double>& v, int cycle) {
    return cycle >= 0 && static_cast<std::size_t>(cycle) < v.size() ? v[static_cast<std::size_t>(cycle)] : NAN;
  }
  bool enabled_ = false;
  double v0_ = NAN;
  std::vector<double> v_heat_, v_cool_;  // per cycle
};

}  // namespace ratchet
