// Displacement and vorticity over cycle windows (docs/output-format.md, "Snapshots",
// `displacement_<a>_<b>.csv`, summary W_rms_<a>_<b>): the body centres kept at the
// start of cycling and at the end of every cycle (outputs.displacement), compared per
// window with observe/displacement_field.hpp.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/run/accumulator.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

class DisplacementWindows final : public Accumulator {
 public:
  // Snapshot 0 is the first state when it already is the start of cycling.
  DisplacementWindows(const World& world, const CycleClock& clock);
  bool enabled() const { return scene_.outputs.displacement_cell > 0.0; }
  void after_step(const World& world, const ClockTick& tick) override;
  // W_rms of each window into `summary` (null when the run did not reach its end) and
  // DIR/displacement_<a>_<b>.csv for each window reached.
  void finish(const std::string& out_dir, nlohmann::json& summary) const;
  void finish(const RunEnd& end, nlohmann::json& summary) const override;  // the above, thermal runs with files
  nlohmann::json save() const override;
  void restore(const nlohmann::json& j) override;

 private:
  const SceneDef& scene_;
  std::vector<std::vector<Vec3>> snapshots_;  // centres at the start of cycling and each cycle end
};

}  // namespace ratchet
