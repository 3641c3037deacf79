#include "ratchet/run/observers.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>

#include "ratchet/io/atomic_file.hpp"
#include "ratchet/io/run_output.hpp"
#include "ratchet/observe/bed_volume.hpp"
#include "ratchet/observe/displacement_field.hpp"
#include "ratchet/observe/peaks.hpp"
#include "ratchet/observe/vtk_writer.hpp"
#include "ratchet/observe/wall_pressure.hpp"
#include "ratchet/thermal/thermal_protocol.hpp"

namespace ratchet {

namespace {

// A stage mark (end of heating, of cooling, of a cycle) counts as reached by a state
// within kStageMarkTol h below it. t is accumulated step by step (t += h), so after N
// steps it is off the exact N h by up to N ulp(t): 17,000 steps of h = 0.004 from
// t = 20 left the end of the last cycle 9e-12 = 2.2e-9 h short, and 1e-9 h missed it
// (no last cycle-end snapshot, no W_rms of the windows ending there). 1e-4 h covers
// the worst case of the paper tier (140,000 steps to t = 560: 2e-6 h) with a margin,
// and is far below the step, so no mark moves to another step.
constexpr double kStageMarkTol = 1e-4;

std::vector<int> side_wall_indices(const SceneDef& s) {
  std::vector<int> out;
  for (std::size_t w = 0; w < s.container.walls.size(); ++w)
    if (s.container.walls[w].role == WallRole::Side) out.push_back(static_cast<int>(w));
  return out;
}

}  // namespace

RunObservers::RunObservers(const World& world, std::string out_dir)
    : scene_(world.scene()), out_dir_(std::move(out_dir)) {
  const OutputSettings& o = scene_.outputs;
  thermal_ = scene_.thermal.enabled && scene_.thermal.cycles > 0;
  if (o.volume) columns_.push_back("V_over_V0");
  if (o.segment_forces)
    for (std::size_t k = 0; k < side_wall_indices(scene_).size(); ++k) columns_.push_back("wall_force_seg_" + std::to_string(k));
  if (o.volume) v0_ = bed_volume(world);
  settle_pending_ = world.settling();
  // The start of cycling is the first state with t >= start_time (within round-off):
  // the initial state when start_time is 0, or a packing (run/packing.hpp) that ends there.
  started_ = thermal_ && world.state().t >= scene_.thermal.start_time - 1e-9 * scene_.dt;
  if (started_ && o.displacement_cell > 0.0) snapshots_.push_back(world.state().x);
  t_prev_ = world.state().t;
}

std::vector<Vec3> RunObservers::bed_points(const World& world) {
  const SceneDef& s = world.scene();
  const State& st = world.state();
  std::vector<Vec3> pts;
  const double d = 1.0 / std::sqrt(3.0);
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    const BodyDef& b = s.bodies[i];
    if (b.fixed) continue;
    const double sc = world.body_scale(static_cast<int>(i));
    if (b.kind == ShapeKind::Sphere) {
      const double r = b.radius * sc;
      for (int a = 0; a < 3; ++a)
        for (double sign : {-1.0, 1.0}) pts.push_back(st.x[i] + sign * r * Vec3::Unit(a));
      for (double sx : {-d, d})
        for (double sy : {-d, d})
          for (double sz : {-d, d}) pts.push_back(st.x[i] + r * Vec3(sx, sy, sz));
    } else {
      const Mat3 R = st.q[i].toRotationMatrix();
      for (const Vec3& v : s.shapes[static_cast<std::size_t>(b.shape)].vertices) pts.push_back(st.x[i] + sc * (R * v));
    }
  }
  return pts;
}

double RunObservers::bed_volume(const World& world) { return convex_hull_volume(bed_points(world)); }

void RunObservers::extra_values(const World& world, std::vector<double>& values) const {
  values.clear();
  const OutputSettings& o = scene_.outputs;
  if (o.volume) values.push_back(bed_volume(world) / v0_);
  if (o.segment_forces) {
    const std::vector<int> sides = side_wall_indices(scene_);
    std::vector<double> f(sides.size(), 0.0);
    for (const SolverContact& c : world.contacts()) {
      if (c.b >= 0) continue;
      const int w = -1 - c.b;
      for (std::size_t k = 0; k < sides.size(); ++k)
        if (sides[k] == w) f[k] += c.lambda[0] / scene_.dt;
    }
    values.insert(values.end(), f.begin(), f.end());
  }
}

RunObservers::StageEnds RunObservers::stage_ends(double t_prev, double t) const {
  StageEnds e;
  const ThermalProtocol& p = scene_.thermal;
  const double L = p.cycle_time();
  const double a = t_prev - p.start_time, b = t - p.start_time;
  if (b <= 0.0 || a >= p.cycles * L) return e;
  const int k = std::max(0, static_cast<int>(std::floor(a / L)));
  const double base = k * L;
  const double eps = kStageMarkTol * scene_.dt;  // stage marks that fall on a step: round-off in t
  auto crossed = [&](double mark) { return a < base + mark - eps && b >= base + mark - eps; };
  e.heating = crossed(p.heat_time);
  e.cooling = crossed(p.heat_time + p.hold_time + p.cool_time);
  e.cycle = crossed(L);
  return e;
}

void RunObservers::after_step(const World& world) {
  const double t = world.state().t;
  if (!thermal_) return;
  const ThermalProtocol& p = scene_.thermal;
  const OutputSettings& o = scene_.outputs;
  // With a settle section V0 is the volume where the settle stage ends (the packing's
  // state), so that a run from the packing has the same V0; without one, where
  // cycling starts (the same state).
  if (settle_pending_ && !world.settling()) {
    settle_pending_ = false;
    if (o.volume) v0_ = bed_volume(world);
  }
  // The settled bed's wall profile: averaged over the states of the last
  // settled_profile_time before cycling that this run computes (after the settle stage
  // of a settle section; none when the run starts from a packing that ends at
  // start_time), with the bands fixed by the bed height at the window's first state.
  // The half step keeps the count at round(settled_profile_time / h) whatever the
  // round-off in t.
  if (!started_ && o.settled_profile_time > 0.0 && !world.settling() &&
      t > p.start_time - o.settled_profile_time + 0.5 * scene_.dt) {
    if (!in_settled_window_) {
      in_settled_window_ = true;
      begin_wall_profile(world);
    }
    accumulate_wall_profile(world);
  }
  // Start of cycling: reference volume and the first snapshot, once (a state a few ulps
  // below start_time reaches the mark, and so would the next step).
  if (!started_ && t >= p.start_time - 1e-9 * scene_.dt) {
    started_ = true;
    if (in_settled_window_) {
      in_settled_window_ = false;
      flush_wall_profile(world, -1);
    }
    if (o.volume && !scene_.settle.enabled) v0_ = bed_volume(world);
    if (o.displacement_cell > 0.0) snapshots_.push_back(world.state().x);
  }
  const double tc = t - p.start_time;
  if (tc > 0.0 && tc <= p.cycles * p.cycle_time() + kStageMarkTol * scene_.dt) {
    // Clamped: t can land a few ulps past start_time or the end of the last cycle.
    const int k = std::max(
        0, std::min(p.cycles - 1, static_cast<int>(std::floor((tc - kStageMarkTol * scene_.dt) / p.cycle_time()))));
    while (static_cast<int>(cycles_.size()) <= k) {
      cycles_.emplace_back();
      cycles_.back().cycle = static_cast<int>(cycles_.size()) - 1;
      cycles_.back().peak_pressure = -HUGE_VAL;
    }
    CycleRecord& c = cycles_[static_cast<std::size_t>(k)];
    // Peak of the block-averaged pressure; a block never spans two cycles.
    if (block_cycle_ != k) { block_sum_ = 0.0; block_time_ = 0.0; block_start_ = t_prev_; block_cycle_ = k; }
    block_sum_ += world.pressure() * scene_.dt;
    block_time_ += scene_.dt;
    if (block_time_ >= o.pressure_window - 1e-9 * scene_.dt) {
      const double P = block_sum_ / block_time_;
      if (P > c.peak_pressure) { c.peak_pressure = P; c.t_peak = 0.5 * (block_start_ + t); }
      block_sum_ = 0.0;
      block_time_ = 0.0;
      block_start_ = t;
    }
    if (in_cold_hold_) accumulate_wall_profile(world);
    c.contacts_sum += world.stats().contacts;
    c.iterations_sum += world.stats().iterations;
    ++c.steps;
    c.unconverged += world.stats().converged ? 0 : 1;
    const bool vtk = std::find(o.vtk_cycles.begin(), o.vtk_cycles.end(), k) != o.vtk_cycles.end();
    const StageEnds ends = stage_ends(t_prev_, t);
    if (ends.heating) {
      if (o.volume) c.v_heat = bed_volume(world) / v0_;
      if (vtk) write_vtk(world, "cycle" + std::to_string(k) + "_end_heating");
    }
    if (ends.cooling) {
      if (o.volume) c.v_cool = bed_volume(world) / v0_;
      if (vtk) write_vtk(world, "cycle" + std::to_string(k) + "_end_cooling");
      if (o.wall_profile_bins > 0) {
        in_cold_hold_ = true;
        begin_wall_profile(world);
        accumulate_wall_profile(world);  // a zero-length hold still gets this step
      }
    }
    if (ends.cycle) {
      if (in_cold_hold_) flush_wall_profile(world, k);
      if (o.displacement_cell > 0.0) snapshots_.push_back(world.state().x);
    }
  }
  t_prev_ = t;
}

// A new time-averaged profile (cold hold or settled window): the bed height now fixes the bands.
void RunObservers::begin_wall_profile(const World& world) {
  profile_impulse_.assign(static_cast<std::size_t>(scene_.outputs.wall_profile_bins), 0.0);
  profile_time_ = 0.0;
  profile_height_ = world.bed_height();
}

// One step of the cold hold: side-wall impulses binned by height (the bed height at the
// end of cooling fixes the bins).
void RunObservers::accumulate_wall_profile(const World& world) {
  const ContainerDef& c = scene_.container;
  if (c.type != ContainerDef::Type::Cone || profile_height_ <= 0.0) return;
  std::vector<double> z, f;
  for (const SolverContact& sc : world.contacts()) {
    if (sc.b >= 0 || c.walls[static_cast<std::size_t>(-1 - sc.b)].role != WallRole::Side) continue;
    z.push_back(sc.geometry.point.z());
    f.push_back(sc.lambda[0] / scene_.dt);
  }
  const std::vector<double> stress = wall_stress_profile(z, f, world.state().s_c * c.bottom_radius, c.opening_angle_deg,
                                                         c.segments, profile_height_, scene_.outputs.wall_profile_bins);
  for (std::size_t k = 0; k < stress.size(); ++k) profile_impulse_[k] += stress[k] * scene_.dt;
  profile_time_ += scene_.dt;
}

// Time-averaged wall stress per height band over the cold hold of `cycle`.
void RunObservers::flush_wall_profile(const World& world, int cycle) {
  in_cold_hold_ = false;
  if (profile_time_ <= 0.0) return;
  const double H = profile_height_;
  const int bins = scene_.outputs.wall_profile_bins;
  std::vector<double> stress(profile_impulse_);
  for (double& s : stress) s /= profile_time_;
  for (int k = 0; k < bins; ++k) {
    std::ostringstream row;
    row << cycle << ',' << format_double(world.state().t) << ',' << k << ',' << format_double(H * k / bins) << ','
        << format_double(H * (k + 1) / bins) << ',' << format_double(stress[static_cast<std::size_t>(k)]);
    profile_rows_.push_back(row.str());
  }
}

void RunObservers::write_vtk(const World& world, const std::string& tag) const {
  if (out_dir_.empty()) return;
  const std::string dir = out_dir_ + "/vtk";
  std::filesystem::create_directories(dir);
  const SceneDef& s = world.scene();
  const State& st = world.state();
  std::vector<VtkBody> bodies;
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    const BodyDef& b = s.bodies[i];
    VtkBody vb;
    vb.id = static_cast<int>(i);
    vb.velocity = st.v[i];
    const double sc = world.body_scale(static_cast<int>(i));
    if (b.kind == ShapeKind::Sphere) {
      vb.vertices.push_back(st.x[i]);
      vb.sphere_radius = b.radius * sc;
    } else {
      const ConvexPolyhedron& shape = s.shapes[static_cast<std::size_t>(b.shape)];
      const Mat3 R = st.q[i].toRotationMatrix();
      for (const Vec3& v : shape.vertices) vb.vertices.push_back(st.x[i] + sc * (R * v));
      vb.faces = shape.faces;
    }
    bodies.push_back(std::move(vb));
  }
  write_particles_vtk(dir + "/particles_" + tag + ".vtk", bodies);
  std::vector<VtkContact> contacts;
  for (const SolverContact& c : world.contacts()) {
    if (c.lambda[0] <= 0.0) continue;
    VtkContact vc;
    vc.a = st.x[c.a];
    vc.b = c.b >= 0 ? st.x[c.b] : c.geometry.point;
    vc.normal_force = c.lambda[0] / s.dt;
    vc.body_a = c.a;
    vc.body_b = c.b;
    contacts.push_back(vc);
  }
  write_contact_network_vtk(dir + "/contacts_" + tag + ".vtk", contacts);
}

nlohmann::json RunObservers::finish(const World& world) {
  nlohmann::json summary;
  const OutputSettings& o = scene_.outputs;
  if (o.volume) summary["V_over_V0_end"] = bed_volume(world) / v0_;
  if (!thermal_) return summary;
  // Steady-state window: the scene's, or the second half of the cycles.
  const int n = static_cast<int>(cycles_.size());
  const int first = o.steady_first >= 0 ? o.steady_first : scene_.thermal.cycles / 2;
  const int last = o.steady_last >= 0 ? o.steady_last : scene_.thermal.cycles - 1;
  std::vector<CyclePeak> peaks;
  for (const CycleRecord& c : cycles_) peaks.push_back({c.cycle, c.peak_pressure, c.t_peak});
  MeanPeak mp;
  if (n > 0 && first <= std::min(last, n - 1)) mp = mean_peak(peaks, first, std::min(last, n - 1));
  summary["P_max"] = mp.count > 0 ? nlohmann::json(mp.mean) : nlohmann::json(nullptr);
  summary["P_max_std"] = std::isfinite(mp.stddev) ? nlohmann::json(mp.stddev) : nlohmann::json(nullptr);
  summary["steady_cycles"] = {first, last};
  summary["cycles_completed"] = n;
  if (out_dir_.empty()) return summary;
  if (o.cycles) {
    std::ostringstream csv;
    csv << "cycle,peak_pressure,t_peak,V_over_V0_end_heating,V_over_V0_end_cooling,contacts_mean,iterations_mean,"
           "unconverged_steps\n";
    for (const CycleRecord& c : cycles_)
      csv << c.cycle << ',' << format_double(c.peak_pressure) << ',' << format_double(c.t_peak) << ','
          << format_double(c.v_heat) << ',' << format_double(c.v_cool) << ','
          << format_double(c.contacts_sum / std::max<long long>(1, c.steps)) << ','
          << format_double(c.iterations_sum / std::max<long long>(1, c.steps)) << ',' << c.unconverged << '\n';
    write_file_atomic(out_dir_ + "/cycles.csv", csv.str());
  }
  if (o.wall_profile_bins > 0) {
    std::ostringstream csv;
    csv << "cycle,t,bin,z_lo,z_hi,wall_stress\n";
    for (const std::string& r : profile_rows_) csv << r << '\n';
    write_file_atomic(out_dir_ + "/wall_profile.csv", csv.str());
  }
  if (o.displacement_cell > 0.0) {
    const double cell = o.displacement_cell;
    const double r_extent = 1.5 * scene_.container.bottom_radius;
    const int nr = static_cast<int>(std::ceil(r_extent / cell));
    for (const auto& [a, b] : o.displacement_windows) {
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
      write_file_atomic(out_dir_ + "/displacement_" + std::to_string(a) + "_" + std::to_string(b) + ".csv", csv.str());
    }
  }
  return summary;
}

}  // namespace ratchet
