#include "ratchet/run/observers.hpp"

#include <algorithm>
#include <sstream>

#include "ratchet/io/atomic_file.hpp"
#include "ratchet/observe/wall_forces.hpp"
#include "ratchet/run/run_output.hpp"

namespace ratchet {

RunObservers::RunObservers(const World& world, std::string out_dir)
    : scene_(world.scene()),
      out_dir_(std::move(out_dir)),
      first_step_(world.state().step),
      clock_(world.scene(), world.state().t, world.settling()),
      volume_(world),
      peaks_(world.scene()),
      profile_(world.scene()),
      displacement_(world, clock_),
      stages_(world, clock_),
      vtk_(world, out_dir_) {
  add_columns();
}

void RunObservers::add_columns() {
  const OutputSettings& o = scene_.outputs;
  if (o.volume) columns_.push_back("V_over_V0");
  if (o.segment_forces)
    for (std::size_t k = 0; k < side_wall_indices(scene_).size(); ++k) columns_.push_back("wall_force_seg_" + std::to_string(k));
}

RunObservers::RunObservers(const World& world, std::string out_dir, const nlohmann::json& saved)
    : scene_(world.scene()),
      out_dir_(std::move(out_dir)),
      first_step_(saved.at("first_step").get<std::int64_t>()),
      clock_(world.scene(), world.state().t, world.settling()),
      volume_(world),
      peaks_(world.scene()),
      profile_(world.scene()),
      displacement_(world, clock_),
      stages_(world, clock_),
      vtk_(world, out_dir_, false) {
  add_columns();
  clock_.restore(saved.at("clock"));
  volume_.restore(saved.at("volume"));
  peaks_.restore(saved.at("peaks"));
  stats_.restore(saved.at("cycle_stats"));
  profile_.restore(saved.at("wall_profile"));
  displacement_.restore(saved.at("displacement"));
  stages_.restore(saved.at("stage_fields"));
  vtk_.restore(saved.at("vtk"));
}

nlohmann::json RunObservers::save() const {
  return {{"first_step", first_step_},   {"clock", clock_.save()},
          {"volume", volume_.save()},   {"peaks", peaks_.save()},   {"cycle_stats", stats_.save()},
          {"wall_profile", profile_.save()}, {"displacement", displacement_.save()}, {"stage_fields", stages_.save()},
          {"vtk", vtk_.save()}};
}

void RunObservers::extra_values(const World& world, std::vector<double>& values) const {
  values.clear();
  if (volume_.enabled()) values.push_back(volume_.ratio(world));
  if (scene_.outputs.segment_forces) {
    const std::vector<double> f = side_segment_forces(scene_, world.contacts());
    values.insert(values.end(), f.begin(), f.end());
  }
}

void RunObservers::after_step(const World& world) {
  const ClockTick tick = clock_.tick(world.state().t, world.settling());
  volume_.after_step(world, tick);
  profile_.after_step(world, tick);
  displacement_.after_step(world, tick);
  stages_.after_step(world, tick);
  peaks_.after_step(world, tick);
  stats_.after_step(world, tick);
  vtk_.after_step(world, tick);
}

void RunObservers::write_cycles(const std::string& path) const {
  std::ostringstream csv;
  csv << "cycle,peak_pressure,t_peak,V_over_V0_end_heating,V_over_V0_end_cooling,contacts_mean,iterations_mean,"
         "unconverged_steps\n";
  for (const CyclePeak& p : peaks_.peaks()) {
    const CycleSolverStats s = stats_.at(p.cycle);
    csv << p.cycle << ',' << format_double(p.value) << ',' << format_double(p.time) << ','
        << format_double(volume_.at_end_of_heating(p.cycle)) << ','
        << format_double(volume_.at_end_of_cooling(p.cycle)) << ','
        << format_double(s.contacts_sum / std::max<long long>(1, s.steps)) << ','
        << format_double(s.iterations_sum / std::max<long long>(1, s.steps)) << ',' << s.unconverged << '\n';
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
  volume_.summarize(world, summary);
  if (!clock_.thermal()) return summary;
  peaks_.summarize(clock_.cycles_reached(), summary);
  summary["cycles_completed"] = clock_.cycles_reached();
  if (out_dir_.empty()) return summary;
  if (scene_.outputs.cycles) write_cycles(out_dir_ + "/cycles.csv");
  if (scene_.outputs.wall_profile_bins > 0) profile_.write(out_dir_);
  displacement_.finish(out_dir_, summary);
  stages_.write(out_dir_);
  return summary;
}

}  // namespace ratchet
