#include "ratchet/run/vtk_snapshots.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "ratchet/core/contact_side.hpp"
#include "ratchet/io/json_numbers.hpp"
#include "ratchet/observe/bed_geometry.hpp"
#include "ratchet/solver/local_coulomb.hpp"

namespace ratchet {

VtkSnapshot take_vtk_snapshot(const World& world) {
  const SceneDef& s = world.scene();
  const State& st = world.state();
  VtkSnapshot snap;
  snap.time = {st.t, st.step};
  PlacedBody placed;
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    const int id = static_cast<int>(i);
    place_body(s, st, id, placed);
    VtkBody vb;
    vb.id = id;
    vb.velocity = st.v[i];
    vb.angular_velocity = st.w[i];
    vb.scale = body_scale(s.bodies[i], st.s_p);
    // Drawn as its kind says (scene/shape_kinds.hpp): faces, or a glyph at the centre.
    vb.sphere_radius = placed.sphere_radius;
    vb.volume = placed.volume;
    if (placed.faces != nullptr) {
      vb.vertices = placed.points;
      vb.faces = *placed.faces;
    } else {
      vb.vertices.push_back(st.x[i]);
    }
    snap.bodies.push_back(std::move(vb));
  }
  const double h = s.dt;
  std::vector<double> wall_force(s.container.walls.size(), 0.0);
  for (const SolverContact& c : world.contacts()) {
    VtkContact vc;
    vc.point = c.geometry.point;
    vc.normal = c.geometry.normal;
    vc.normal_force = c.lambda[0] / h * c.geometry.normal;
    vc.tangential_force = (c.lambda[1] * c.t1 + c.lambda[2] * c.t2) / h;
    vc.gap = c.geometry.gap;
    vc.body_a = c.a;
    vc.body_b = c.b;
    vc.from = st.x[static_cast<std::size_t>(c.a)];
    vc.to = is_wall(c.b) ? c.geometry.point : st.x[static_cast<std::size_t>(c.b)];
    // On the cone as the solver's slide test reads it (solver/local_coulomb.hpp).
    Eigen::Vector2d slide;
    vc.status = !(c.lambda[0] > 0.0) ? kContactOpen : slide_direction(c.lambda, c.mu, slide) ? kContactSlip : kContactStick;
    snap.contacts.push_back(vc);
    if (is_wall(c.b)) wall_force[static_cast<std::size_t>(wall_index(c.b))] += c.lambda[0];
  }
  snap.container = container_mesh(s, st.s_c);
  for (int w : snap.container.wall) {
    snap.wall_normal.push_back(s.container.walls[static_cast<std::size_t>(w)].normal);
    snap.wall_force.push_back(wall_force[static_cast<std::size_t>(w)] / h);
  }
  return snap;
}

std::string vtk_step_tag(std::int64_t step) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "step%08lld", static_cast<long long>(step));
  return buf;
}

VtkSnapshots::VtkSnapshots(const World& world, std::string out_dir, bool first_state)
    : scene_(world.scene()), out_dir_(std::move(out_dir)) {
  if (first_state && !out_dir_.empty() && scene_.outputs.vtk_every > 0) write(world, vtk_step_tag(world.state().step));
}

namespace {

nlohmann::json json_entries(const std::vector<PvdEntry>& entries) {
  nlohmann::json a = nlohmann::json::array();
  for (const PvdEntry& e : entries) a.push_back({json_number(e.time), e.file});
  return a;
}

std::vector<PvdEntry> entries_from_json(const nlohmann::json& j) {
  std::vector<PvdEntry> entries;
  for (const auto& e : j) entries.push_back({number_from_json(e.at(0)), e.at(1).get<std::string>()});
  return entries;
}

}  // namespace

nlohmann::json VtkSnapshots::save() const {
  return {{"last_indexed_step", last_indexed_step_}, {"particles", json_entries(particles_)},
          {"contacts", json_entries(contacts_)}, {"container", json_entries(container_)},
          {"force_chains", json_entries(force_chains_)}};
}

void VtkSnapshots::restore(const nlohmann::json& j) {
  last_indexed_step_ = j.at("last_indexed_step").get<std::int64_t>();
  particles_ = entries_from_json(j.at("particles"));
  contacts_ = entries_from_json(j.at("contacts"));
  container_ = entries_from_json(j.at("container"));
  // Checkpoints made before force chains were written have none.
  force_chains_ = entries_from_json(j.value("force_chains", nlohmann::json::array()));
  if (out_dir_.empty() || particles_.empty()) return;
  const std::string dir = out_dir_ + "/vtk";
  write_pvd(dir + "/particles.pvd", particles_);
  write_pvd(dir + "/contacts.pvd", contacts_);
  if (!force_chains_.empty()) write_pvd(dir + "/force_chains.pvd", force_chains_);
  if (!container_.empty()) write_pvd(dir + "/container.pvd", container_);
}

void VtkSnapshots::after_step(const World& world, const ClockTick& tick) {
  if (out_dir_.empty()) return;
  const std::int64_t k = world.state().step;
  const int every = scene_.outputs.vtk_every;
  if (every > 0 && (k % every == 0 || k == scene_.steps)) write(world, vtk_step_tag(k));
  if (tick.cycle < 0) return;
  const std::vector<int>& cycles = scene_.outputs.vtk_cycles;
  if (std::find(cycles.begin(), cycles.end(), tick.cycle) == cycles.end()) return;
  const std::string c = std::to_string(tick.cycle);
  if (tick.ends.heating) write(world, "cycle" + c + "_end_heating");
  if (tick.ends.cooling) write(world, "cycle" + c + "_end_cooling");
}

void VtkSnapshots::write(const World& world, const std::string& tag) {
  if (out_dir_.empty()) return;
  write(take_vtk_snapshot(world), tag);
}

void VtkSnapshots::write(const VtkSnapshot& snap, const std::string& tag) {
  const std::string dir = out_dir_ + "/vtk";
  std::filesystem::create_directories(dir);
  const std::string particles = "particles_" + tag + ".vtp", contacts = "contacts_" + tag + ".vtp",
                    container = "container_" + tag + ".vtp", chains = "force_chains_" + tag + ".vtp";
  const bool walls = !snap.container.polygons.empty();
  const VtkEncoding enc = scene_.outputs.vtk_ascii ? VtkEncoding::Ascii : VtkEncoding::Binary;
  write_particles_vtp(dir + "/" + particles, snap.bodies, snap.time, enc);
  write_contacts_vtp(dir + "/" + contacts, snap.contacts, snap.time, enc);
  write_force_chains_vtp(dir + "/" + chains, snap.contacts, snap.time, enc);
  if (walls)
    write_container_vtp(dir + "/" + container, snap.container, snap.wall_normal, snap.wall_force, snap.time, enc);
  // A state written under two tags (a stage end on a step of vtk_every) is indexed once,
  // under the first: one time, one data set.
  if (snap.time.step == last_indexed_step_) return;
  last_indexed_step_ = snap.time.step;
  particles_.push_back({snap.time.t, particles});
  contacts_.push_back({snap.time.t, contacts});
  force_chains_.push_back({snap.time.t, chains});
  write_pvd(dir + "/particles.pvd", particles_);
  write_pvd(dir + "/contacts.pvd", contacts_);
  write_pvd(dir + "/force_chains.pvd", force_chains_);
  if (walls) {
    container_.push_back({snap.time.t, container});
    write_pvd(dir + "/container.pvd", container_);
  }
}

}  // namespace ratchet
