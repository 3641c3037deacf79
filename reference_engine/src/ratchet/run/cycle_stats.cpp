#include "ratchet/run/cycle_stats.hpp"

#include <algorithm>

#include "ratchet/io/json_numbers.hpp"
#include "ratchet/run/run_output.hpp"

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

nlohmann::json CycleStats::save() const {
  nlohmann::json a = nlohmann::json::array();
  for (const CycleSolverStats& c : cycles_)
    a.push_back({json_number(c.contacts_sum), json_number(c.iterations_sum), c.steps, c.unconverged});
  return a;
}

void CycleStats::restore(const nlohmann::json& j) {
  cycles_.clear();
  for (const auto& c : j)
    cycles_.push_back({number_from_json(c.at(0)), number_from_json(c.at(1)), c.at(2).get<long long>(),
                       c.at(3).get<long long>()});
}

void CycleStats::cycle_columns(std::vector<std::string>& names) const {
  names.insert(names.end(), {"contacts_mean", "iterations_mean", "unconverged_steps"});
}

void CycleStats::cycle_cells(int cycle, std::vector<std::string>& cells) const {
  const CycleSolverStats s = at(cycle);
  cells.push_back(format_double(s.contacts_sum / std::max<long long>(1, s.steps)));
  cells.push_back(format_double(s.iterations_sum / std::max<long long>(1, s.steps)));
  cells.push_back(std::to_string(s.unconverged));
}

}  // namespace ratchet
