#include "ratchet/run/wall_profile.hpp"

#include <sstream>

#include "ratchet/io/atomic_file.hpp"
#include "ratchet/io/json_numbers.hpp"
#include "ratchet/observe/bed_geometry.hpp"
#include "ratchet/observe/wall_forces.hpp"
#include "ratchet/observe/wall_pressure.hpp"
#include "ratchet/run/run_output.hpp"

namespace ratchet {

namespace {

// Steps: the settled window's edge midway between two states, where no round-off in t
// can move a state across it.
constexpr double kWindowEdge = 0.5;

}  // namespace

nlohmann::json WallProfile::save() const {
  return {{"rows", rows_}, {"impulse", json_numbers(impulse_)}, {"time", json_number(time_)},
          {"height", json_number(height_)}, {"in_cold_hold", in_cold_hold_}, {"in_settled_window", in_settled_window_}};
}

void WallProfile::restore(const nlohmann::json& j) {
  rows_ = j.at("rows").get<std::vector<std::string>>();
  impulse_ = numbers_from_json(j.at("impulse"));
  time_ = number_from_json(j.at("time"));
  height_ = number_from_json(j.at("height"));
  in_cold_hold_ = j.at("in_cold_hold").get<bool>();
  in_settled_window_ = j.at("in_settled_window").get<bool>();
}

void WallProfile::after_step(const World& world, const ClockTick& tick) {
  const OutputSettings& o = scene_.outputs;
  // The settled bed's window: the states of the last settled_profile_time before
  // cycling that this run computes (after the settle stage of a settle section; none
  // when the run starts from a packing that ends at start_time). The half step keeps
  // the count at round(settled_profile_time / h) whatever the round-off in t.
  if (tick.before_cycling && o.settled_profile_time > 0.0 && !tick.settling &&
      tick.t > scene_.thermal.start_time - o.settled_profile_time + kWindowEdge * scene_.dt) {
    if (!in_settled_window_) {
      in_settled_window_ = true;
      begin(world);
    }
    accumulate(world);
  }
  if (tick.cycling_starts && in_settled_window_) {
    in_settled_window_ = false;
    flush(world, -1);
  }
  if (tick.cycle < 0) return;
  if (in_cold_hold_) accumulate(world);
  if (tick.ends.cooling && o.wall_profile_bins > 0) {
    in_cold_hold_ = true;
    begin(world);
    accumulate(world);  // a zero-length hold still gets this step
  }
  if (tick.ends.cycle && in_cold_hold_) flush(world, tick.cycle);
}

// A new average: the bed height now fixes the bands.
void WallProfile::begin(const World& world) {
  impulse_.assign(static_cast<std::size_t>(scene_.outputs.wall_profile_bins), 0.0);
  time_ = 0.0;
  height_ = bed_height(world.scene(), world.state());
}

// One step: side-wall stress per band, times h.
void WallProfile::accumulate(const World& world) {
  const ContainerDef& c = scene_.container;
  if (c.type != ContainerDef::Type::Cone || height_ <= 0.0) return;
  side_wall_contacts(scene_, world.contacts(), z_, force_);
  const std::vector<double> stress = wall_stress_profile(z_, force_, world.state().s_c * c.bottom_radius,
                                                         c.opening_angle_deg, c.segments, height_,
                                                         scene_.outputs.wall_profile_bins);
  for (std::size_t k = 0; k < stress.size(); ++k) impulse_[k] += stress[k] * scene_.dt;
  time_ += scene_.dt;
}

// The time average of the current window as rows of `cycle`.
void WallProfile::flush(const World& world, int cycle) {
  in_cold_hold_ = false;
  if (time_ <= 0.0) return;
  const double H = height_;
  const int bins = scene_.outputs.wall_profile_bins;
  std::vector<double> stress(impulse_);
  for (double& s : stress) s /= time_;
  for (int k = 0; k < bins; ++k) {
    std::ostringstream row;
    row << cycle << ',' << format_double(world.state().t) << ',' << k << ',' << format_double(H * k / bins) << ','
        << format_double(H * (k + 1) / bins) << ',' << format_double(stress[static_cast<std::size_t>(k)]);
    rows_.push_back(row.str());
  }
}

void WallProfile::write(const std::string& out_dir) const {
  std::ostringstream csv;
  csv << "cycle,t,bin,z_lo,z_hi,wall_stress\n";
  for (const std::string& r : rows_) csv << r << '\n';
  write_file_atomic(out_dir + "/wall_profile.csv", csv.str());
}

void WallProfile::finish(const RunEnd& end, nlohmann::json&) const {
  if (end.clock.thermal() && !end.out_dir.empty() && scene_.outputs.wall_profile_bins > 0) write(end.out_dir);
}

}  // namespace ratchet
