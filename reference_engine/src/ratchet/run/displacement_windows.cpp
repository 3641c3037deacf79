#include "ratchet/run/displacement_windows.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "ratchet/io/atomic_file.hpp"
#include "ratchet/io/json_numbers.hpp"
#include "ratchet/observe/displacement_field.hpp"
#include "ratchet/run/run_output.hpp"

namespace ratchet {

DisplacementWindows::DisplacementWindows(const World& world, const CycleClock& clock) : scene_(world.scene()) {
  if (clock.started_at_first_state() && enabled()) snapshots_.push_back(world.state().x);
}

void DisplacementWindows::after_step(const World& world, const ClockTick& tick) {
  if (!enabled()) return;
  if (tick.cycling_starts) snapshots_.push_back(world.state().x);
  if (tick.cycle >= 0 && tick.ends.cycle) snapshots_.push_back(world.state().x);
}

nlohmann::json DisplacementWindows::save() const {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& s : snapshots_) a.push_back(json_vec3s(s));
  return a;
}

void DisplacementWindows::restore(const nlohmann::json& j) {
  snapshots_.clear();
  for (const auto& s : j) snapshots_.push_back(vec3s_from_json(s));
}

void DisplacementWindows::finish(const std::string& out_dir, nlohmann::json& summary) const {
  if (!enabled()) return;
  const double cell = scene_.outputs.displacement_cell;
  const int nr = radial_cells(scene_.container.bottom_radius, cell);
  for (const auto& [a, b] : scene_.outputs.displacement_windows) {
    const std::string key = "W_rms_" + std::to_string(a) + "_" + std::to_string(b);
    if (b >= static_cast<int>(snapshots_.size())) {
      summary[key] = nullptr;  // the run did not reach the end of cycle b - 1
      continue;
    }
    double top = 0.0;
    for (const Vec3& x : snapshots_[static_cast<std::size_t>(a)]) top = std::max(top, x.z());
    const int nz = static_cast<int>(std::ceil((top + cell) / cell));
    const DisplacementField f = displacement_field(snapshots_[static_cast<std::size_t>(a)],
                                                   snapshots_[static_cast<std::size_t>(b)], cell, nr, nz);
    const VorticityField w = vorticity_field(f);
    const double rms = rms_vorticity(w);
    summary[key] = std::isfinite(rms) ? nlohmann::json(rms) : nlohmann::json(nullptr);
    std::ostringstream csv;
    csv << "ir,iz,r,z,ur,uz,count,w\n";
    for (int iz = 0; iz < nz; ++iz)
      for (int ir = 0; ir < nr; ++ir) {
        const int i = f.index(ir, iz);
        if (f.count[static_cast<std::size_t>(i)] == 0) continue;
        csv << ir << ',' << iz << ',' << format_double((ir + 0.5) * cell) << ',' << format_double((iz + 0.5) * cell)
            << ',' << format_double(f.ur[static_cast<std::size_t>(i)]) << ','
            << format_double(f.uz[static_cast<std::size_t>(i)]) << ',' << f.count[static_cast<std::size_t>(i)] << ','
            << format_double(w.w[static_cast<std::size_t>(i)]) << '\n';
      }
    write_file_atomic(out_dir + "/displacement_" + std::to_string(a) + "_" + std::to_string(b) + ".csv", csv.str());
  }
}

void DisplacementWindows::finish(const RunEnd& end, nlohmann::json& summary) const {
  if (end.clock.thermal() && !end.out_dir.empty()) finish(end.out_dir, summary);
}

}  // namespace ratchet
