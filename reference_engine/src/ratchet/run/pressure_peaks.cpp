#include "ratchet/run/pressure_peaks.hpp"

#include <algorithm>
#include <cmath>

#include "ratchet/io/json_numbers.hpp"
#include "ratchet/observe/wall_pressure.hpp"
#include "ratchet/run/run_output.hpp"
#include "ratchet/run/time_marks.hpp"

namespace ratchet {

void PressurePeaks::after_step(const World& world, const ClockTick& tick) {
  if (tick.cycle < 0) return;
  const int k = tick.cycle;
  while (static_cast<int>(peaks_.size()) <= k)
    peaks_.push_back({static_cast<int>(peaks_.size()), -HUGE_VAL, 0.0});
  CyclePeak& c = peaks_[static_cast<std::size_t>(k)];
  const double dt = scene_.dt;
  if (block_cycle_ != k) { block_sum_ = 0.0; block_time_ = 0.0; block_start_ = tick.t_prev; block_cycle_ = k; }
  block_sum_ += side_wall_pressure(world.scene(), world.state(), world.stats().wall_force_side) * dt;
  block_time_ += dt;
  if (block_time_ >= scene_.outputs.pressure_window - kTimeRoundTol * dt) {
    const double P = block_sum_ / block_time_;
    if (P > c.value) { c.value = P; c.time = 0.5 * (block_start_ + tick.t); }
    block_sum_ = 0.0;
    block_time_ = 0.0;
    block_start_ = tick.t;
  }
}

nlohmann::json PressurePeaks::save() const {
  nlohmann::json peaks = nlohmann::json::array();
  for (const CyclePeak& p : peaks_) peaks.push_back({p.cycle, json_number(p.value), json_number(p.time)});
  return {{"peaks", peaks}, {"block_sum", json_number(block_sum_)}, {"block_time", json_number(block_time_)},
          {"block_start", json_number(block_start_)}, {"block_cycle", block_cycle_}};
}

void PressurePeaks::restore(const nlohmann::json& j) {
  peaks_.clear();
  for (const auto& p : j.at("peaks"))
    peaks_.push_back({p.at(0).get<int>(), number_from_json(p.at(1)), number_from_json(p.at(2))});
  block_sum_ = number_from_json(j.at("block_sum"));
  block_time_ = number_from_json(j.at("block_time"));
  block_start_ = number_from_json(j.at("block_start"));
  block_cycle_ = j.at("block_cycle").get<int>();
}

void PressurePeaks::summarize(int cycles_reached, nlohmann::json& summary) const {
  // Steady-state window: the scene's, or the second half of the cycles.
  const OutputSettings& o = scene_.outputs;
  const int n = cycles_reached;
  const int first = o.steady_first >= 0 ? o.steady_first : scene_.thermal.cycles / 2;
  const int last = o.steady_last >= 0 ? o.steady_last : scene_.thermal.cycles - 1;
  const std::vector<CyclePeak> reached(peaks_.begin(), peaks_.begin() + std::min<std::ptrdiff_t>(n, peaks_.size()));
  MeanPeak mp;
  if (n > 0 && first <= std::min(last, n - 1)) mp = mean_peak(reached, first, std::min(last, n - 1));
  summary["P_max"] = mp.count > 0 ? nlohmann::json(mp.mean) : nlohmann::json(nullptr);
  summary["P_max_std"] = std::isfinite(mp.stddev) ? nlohmann::json(mp.stddev) : nlohmann::json(nullptr);
  summary["steady_cycles"] = {first, last};
}

void PressurePeaks::cycle_columns(std::vector<std::string>& names) const {
  names.insert(names.end(), {"peak_pressure", "t_peak"});
}

void PressurePeaks::cycle_cells(int cycle, std::vector<std::string>& cells) const {
  // Every cycle the clock reached has its entry: this accumulator saw the same ticks.
  const CyclePeak p = static_cast<std::size_t>(cycle) < peaks_.size() ? peaks_[static_cast<std::size_t>(cycle)]
                                                                      : CyclePeak{cycle, -HUGE_VAL, 0.0};
  cells.push_back(format_double(p.value));
  cells.push_back(format_double(p.time));
}

void PressurePeaks::finish(const RunEnd& end, nlohmann::json& summary) const {
  if (end.clock.thermal()) summarize(end.clock.cycles_reached(), summary);
}

}  // namespace ratchet
