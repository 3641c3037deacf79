// Solver statistics per cycle (docs/output-format.md, `cycles.csv`): mean active
// contacts and sweeps per step, and the steps that hit solver.max_iterations.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/run/accumulator.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet {

struct CycleSolverStats {
  double contacts_sum = 0.0, iterations_sum = 0.0;
  long long steps = 0, unconverged = 0;
};

class CycleStats final : public Accumulator {
 public:
  void after_step(const World& world, const ClockTick& tick) override;
  // The sums of `cycle`; zero if it was not reached.
  CycleSolverStats at(int cycle) const {
    return cycle >= 0 && static_cast<std::size_t>(cycle) < cycles_.size() ? cycles_[static_cast<std::size_t>(cycle)]
                                                                           : CycleSolverStats{};
  }
  // contacts_mean, iterations_mean, unconverged_steps
  void cycle_columns(std::vector<std::string>& names) const override;
  void cycle_cells(int cycle, std::vector<std::string>& cells) const override;
  nlohmann::json save() const override;
  void restore(const nlohmann::json& j) override;

 private:
  std::vector<CycleSolverStats> cycles_;
};

}  // namespace ratchet
