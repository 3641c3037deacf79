#include "ratchet/run/volume_ratio.hpp"

#include "ratchet/io/json_numbers.hpp"
#include "ratchet/observe/bed_volume.hpp"
#include "ratchet/run/run_output.hpp"

namespace ratchet {

VolumeRatio::VolumeRatio(const World& world) : enabled_(world.scene().outputs.volume) {
  if (enabled_) v0_ = bed_volume(world.scene(), world.state());
}

double VolumeRatio::ratio(const World& world) const { return bed_volume(world.scene(), world.state()) / v0_; }

void VolumeRatio::after_step(const World& world, const ClockTick& tick) {
  if (!enabled_) return;
  // V0 is the settled bed: where a settle section's stage ends (the packing's state, so
  // a run from the packing has the same V0); without one, where cycling starts.
  if (tick.settle_ended) v0_ = bed_volume(world.scene(), world.state());
  if (tick.cycling_starts && !world.scene().settle.enabled) v0_ = bed_volume(world.scene(), world.state());
  if (tick.cycle < 0) return;
  const std::size_t k = static_cast<std::size_t>(tick.cycle);
  if (v_heat_.size() <= k) {
    v_heat_.resize(k + 1, NAN);
    v_cool_.resize(k + 1, NAN);
  }
  if (tick.ends.heating) v_heat_[k] = ratio(world);
  if (tick.ends.cooling) v_cool_[k] = ratio(world);
}

nlohmann::json VolumeRatio::save() const {
  return {{"v0", json_number(v0_)}, {"heating", json_numbers(v_heat_)}, {"cooling", json_numbers(v_cool_)}};
}

void VolumeRatio::restore(const nlohmann::json& j) {
  v0_ = number_from_json(j.at("v0"));
  v_heat_ = numbers_from_json(j.at("heating"));
  v_cool_ = numbers_from_json(j.at("cooling"));
}

void VolumeRatio::summarize(const World& world, nlohmann::json& summary) const {
  if (enabled_) summary["V_over_V0_end"] = ratio(world);
}

void VolumeRatio::timeseries_columns(std::vector<std::string>& names) const {
  if (enabled_) names.push_back("V_over_V0");
}

void VolumeRatio::timeseries_values(const World& world, std::vector<double>& values) const {
  if (enabled_) values.push_back(ratio(world));
}

void VolumeRatio::cycle_columns(std::vector<std::string>& names) const {
  names.insert(names.end(), {"V_over_V0_end_heating", "V_over_V0_end_cooling"});
}

void VolumeRatio::cycle_cells(int cycle, std::vector<std::string>& cells) const {
  cells.push_back(format_double(at_end_of_heating(cycle)));
  cells.push_back(format_double(at_end_of_cooling(cycle)));
}

void VolumeRatio::finish(const RunEnd& end, nlohmann::json& summary) const { summarize(end.world, summary); }

}  // namespace ratchet
