#include "ratchet/run/cycle_stats.hpp"

namespace ratchet {

void CycleStats::after_step(const World& world, const ClockTick& tick) {
  if (tick.cycle < 0) return;
  const std::size_t k = static_cast<std::size_t>(tick.cycle);
  if (cycles_.size() <= k) cycles_.resize(k + 1);
  CycleSolverStats& c = cycles_[k];
  c.contacts_sum += world.stats().contacts;
  c.iterations_sum += world.stats().iterations;
  ++c.steps;
  c.unconverged += world.stats().converged ? 0 : 1;
}

}  // namespace ratchet
