// Peak wall pressure per cycle and P_max (docs/output-format.md, "Per-cycle peak
// pressure", "P_max"): the side-wall pressure of every step of a cycle, block-averaged
// over outputs.pressure_window, its largest block per cycle, and the mean of those
// peaks over the steady cycles (observe/peaks.hpp).
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/observe/peaks.hpp"
#include "ratchet/run/accumulator.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

class PressurePeaks final : public Accumulator {
 public:
  explicit PressurePeaks(const SceneDef& scene) : scene_(scene) {}
  void after_step(const World& world, const ClockTick& tick) override;
  // peak_pressure, t_peak
  void cycle_columns(std::vector<std::string>& names) const override;
  void cycle_cells(int cycle, std::vector<std::string>& cells) const override;
  // One entry per cycle reached: value -inf when no block closed in it.
  const std::vector<CyclePeak>& peaks() const { return peaks_; }
  // P_max, P_max_std and steady_cycles over the first `cycles_reached` cycles.
  void summarize(int cycles_reached, nlohmann::json& summary) const;
  void finish(const RunEnd& end, nlohmann::json& summary) const override;  // summarize, thermal runs only
  nlohmann::json save() const override;
  void restore(const nlohmann::json& j) override;

 private:
  const SceneDef& scene_;
  std::vector<CyclePeak> peaks_;
  // NSCD wall impulses are intermittent, so single-step values are noisy: the block
  // being averaged, which never spans two cycles.
  double block_sum_ = 0.0, block_time_ = 0.0, block_start_ = 0.0;
  int block_cycle_ = -1;
};

}  // namespace ratchet
