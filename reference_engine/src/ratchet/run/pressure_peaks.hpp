// Peak wall pressure per cycle and P_max (docs/output-format.md, "Per-cycle peak
// pressure", "P_max"): the side-wall pressure of every step of a cycle, block-averaged
// over outputs.pressure_window, its largest block per cycle, and the mean of those
// peaks over the steady cycles (observe/peaks.hpp).
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/observe/peaks.hpp"
#include "ratchet/run/cycle_clock.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

class PressurePeaks {
 public:
  explicit PressurePeaks(const SceneDef& scene) : scene_(scene) {}
  void after_step(const World& world, const ClockTick& tick);
  // One entry per cycle reached: value -inf when no block closed in it.
  const std::vector<CyclePeak>& peaks() const { return peaks_; }
  // P_max, P_max_std and steady_cycles over the first `cycles_reached` cycles.
  void summarize(int cycles_reached, nlohmann::json& summary) const;
  // A checkpoint's record of this accumulator (run/checkpoint.hpp), and its restore.
  nlohmann::json save() const;
  void restore(const nlohmann::json& j);

 private:
  const SceneDef& scene_;
  std::vector<CyclePeak> peaks_;
  // NSCD wall impulses are intermittent, so single-step values are noisy: the block
  // being averaged, which never spans two cycles.
  double block_sum_ = 0.0, block_time_ = 0.0, block_start_ = 0.0;
  int block_cycle_ = -1;
};

}  // namespace ratchet
