#include "ratchet/run/stage_fields.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ratchet/io/atomic_file.hpp"
#include "ratchet/io/json_numbers.hpp"
#include "ratchet/observe/displacement_field.hpp"

namespace ratchet {
namespace {

// 6 significant digits: a cell mean of a stage is already an average over grains whose
// own scatter is far above 1e-6 of it, and it keeps the paper's bed (2000 bodies, 20
// cycles) near 0.2 MB.
std::string short_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

}  // namespace

StageFields::StageFields(const World& world, const CycleClock& clock) : scene_(world.scene()) {
  if (clock.started_at_first_state() && enabled()) start_cycle(world.state().x, 0);
}

void StageFields::start_cycle(const std::vector<Vec3>& x, int cycle) {
  if (cycle == 0) {
    // Same grid as the cycle windows (run/displacement_windows.cpp), taken once so
    // that every cycle's rows share it.
    const double cell = scene_.outputs.displacement_cell;
    double top = 0.0;
    for (const Vec3& p : x) top = std::max(top, p.z());
    nr_ = radial_cells(scene_.container.bottom_radius, cell);
    nz_ = std::max(1, static_cast<int>(std::ceil((top + cell) / cell)));
  }
  start_ = x;
  start_cycle_ = cycle;
}

void StageFields::after_step(const World& world, const ClockTick& tick) {
  if (!enabled()) return;
  const std::vector<Vec3>& x = world.state().x;
  if (tick.cycling_starts) start_cycle(x, 0);
  if (tick.cycle < 0) return;
  // Several marks can fall on one step (a zero-length hold): in protocol order.
  if (tick.ends.heating && start_cycle_ == tick.cycle) {
    heated_ = x;
    heated_cycle_ = tick.cycle;
  }
  if (tick.ends.cooling && heated_cycle_ == tick.cycle && start_cycle_ == tick.cycle) add_rows(tick.cycle, x);
  if (tick.ends.cycle) start_cycle(x, tick.cycle + 1);
}

void StageFields::add_rows(int cycle, const std::vector<Vec3>& cooled) {
  const double cell = scene_.outputs.displacement_cell;
  // Both stages binned where the bodies were at the start of the cycle: the two fields
  // add up cell by cell to the field from the start of the cycle to its end of cooling.
  const DisplacementField h = displacement_field(start_, start_, heated_, cell, nr_, nz_);
  const DisplacementField c = displacement_field(start_, heated_, cooled, cell, nr_, nz_);
  std::string out;
  for (int iz = 0; iz < nz_; ++iz)
    for (int ir = 0; ir < nr_; ++ir) {
      const auto k = static_cast<std::size_t>(h.index(ir, iz));
      if (h.count[k] == 0) continue;
      out += std::to_string(cycle) + ',' + std::to_string(ir) + ',' + std::to_string(iz) + ',' +
             short_number((ir + 0.5) * cell) + ',' + short_number((iz + 0.5) * cell) + ',' +
             std::to_string(h.count[k]) + ',' + short_number(h.ur[k]) + ',' + short_number(h.uz[k]) + ',' +
             short_number(c.ur[k]) + ',' + short_number(c.uz[k]) + '\n';
    }
  rows_ += out;
  heated_.clear();  // kept only until the end of cooling
  heated_cycle_ = -1;
}

void StageFields::write(const std::string& out_dir) const {
  if (!enabled()) return;
  write_file_atomic(out_dir + "/" + kStageFieldsFileName,
                    "cycle,ir,iz,r,z,count,ur_heating,uz_heating,ur_cooling,uz_cooling\n" + rows_);
}

nlohmann::json StageFields::save() const {
  return {{"nr", nr_},
          {"nz", nz_},
          {"start_cycle", start_cycle_},
          {"heated_cycle", heated_cycle_},
          {"start", json_vec3s(start_)},
          {"heated", json_vec3s(heated_)},
          {"rows", rows_}};
}

void StageFields::restore(const nlohmann::json& j) {
  nr_ = j.at("nr").get<int>();
  nz_ = j.at("nz").get<int>();
  start_cycle_ = j.at("start_cycle").get<int>();
  heated_cycle_ = j.at("heated_cycle").get<int>();
  start_ = vec3s_from_json(j.at("start"));
  heated_ = vec3s_from_json(j.at("heated"));
  rows_ = j.at("rows").get<std::string>();
}

void StageFields::finish(const RunEnd& end, nlohmann::json&) const {
  if (end.clock.thermal() && !end.out_dir.empty()) write(end.out_dir);
}

}  // namespace ratchet
