// The wall_force_seg_<k> columns of timeseries.csv (outputs.segment_forces): the normal
// force on each side segment in the last step (observe/wall_forces.hpp). Keeps nothing.
#pragma once

#include "ratchet/run/accumulator.hpp"

namespace ratchet {

class SegmentForces final : public Accumulator {
 public:
  explicit SegmentForces(const SceneDef& scene) : scene_(scene) {}
  void after_step(const World&, const ClockTick&) override {}
  void timeseries_columns(std::vector<std::string>& names) const override;
  void timeseries_values(const World& world, std::vector<double>& values) const override;

 private:
  const SceneDef& scene_;
};

}  // namespace ratchet
