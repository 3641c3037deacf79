#include "ratchet/run/observers.hpp"

#include <sstream>

#include "ratchet/io/atomic_file.hpp"
#include "ratchet/run/accumulators.hpp"

namespace ratchet {

RunObservers::RunObservers(const World& world, std::string out_dir)
    : scene_(world.scene()),
      out_dir_(std::move(out_dir)),
      first_step_(world.state().step),
      clock_(world.scene(), world.state().t, world.settling()) {
  make_accumulators(world, false);
}

RunObservers::RunObservers(const World& world, std::string out_dir, const nlohmann::json& saved)
    : scene_(world.scene()),
      out_dir_(std::move(out_dir)),
      first_step_(saved.at("first_step").get<std::int64_t>()),
      clock_(world.scene(), world.state().t, world.settling()) {
  make_accumulators(world, true);
  clock_.restore(saved.at("clock"));
  for (Held& h : accumulators_)
    if (h.key != nullptr) h.accumulator->restore(saved.at(h.key));
}

void RunObservers::make_accumulators(const World& world, bool resuming) {
  const ObserverSetup setup{world, clock_, out_dir_, resuming};
  for (const AccumulatorEntry& e : accumulator_entries()) accumulators_.push_back({e.key, e.make(setup)});
  for (const Held& h : accumulators_) h.accumulator->timeseries_columns(columns_);
}

nlohmann::json RunObservers::save() const {
  nlohmann::json saved = {{"first_step", first_step_}, {"clock", clock_.save()}};
  for (const Held& h : accumulators_)
    if (h.key != nullptr) saved[h.key] = h.accumulator->save();
  return saved;
}

void RunObservers::extra_values(const World& world, std::vector<double>& values) const {
  values.clear();
  for (const Held& h : accumulators_) h.accumulator->timeseries_values(world, values);
}

void RunObservers::after_step(const World& world) {
  const ClockTick tick = clock_.tick(world.state().t, world.settling());
  for (Held& h : accumulators_) h.accumulator->after_step(world, tick);
}

// One row per cycle reached, the accumulators' cells after the cycle number.
void RunObservers::write_cycles(const std::string& path) const {
  std::vector<std::string> names = {"cycle"};
  for (const Held& h : accumulators_) h.accumulator->cycle_columns(names);
  std::ostringstream csv;
  std::vector<std::string> cells;
  for (int k = -1; k < clock_.cycles_reached(); ++k) {
    cells.clear();
    if (k < 0) {
      cells = names;
    } else {
      cells.push_back(std::to_string(k));
      for (const Held& h : accumulators_) h.accumulator->cycle_cells(k, cells);
    }
    for (std::size_t c = 0; c < cells.size(); ++c) csv << (c > 0 ? "," : "") << cells[c];
    csv << '\n';
  }
  write_file_atomic(path, csv.str());
}

nlohmann::json RunObservers::finish(const World& world) {
  nlohmann::json summary;
  // Every observable below may rest on steps the solver left at its cap: say how many.
  const std::int64_t steps = world.state().step - first_step_;
  summary["unconverged_steps"] = world.totals().unconverged_steps;
  summary["unconverged_fraction"] =
      steps > 0 ? static_cast<double>(world.totals().unconverged_steps) / static_cast<double>(steps) : 0.0;
  const RunEnd end{world, clock_, out_dir_};
  for (const Held& h : accumulators_) h.accumulator->finish(end, summary);
  if (!clock_.thermal()) return summary;
  summary["cycles_completed"] = clock_.cycles_reached();
  if (!out_dir_.empty() && scene_.outputs.cycles) write_cycles(out_dir_ + "/cycles.csv");
  return summary;
}

}  // namespace ratchet
