#include "ratchet/run/vtk_snapshots.hpp"

#include <algorithm>
#include <filesystem>
#include <vector>

#include "ratchet/observe/bed_geometry.hpp"
#include "ratchet/observe/vtk_writer.hpp"

namespace ratchet {

void VtkSnapshots::after_step(const World& world, const ClockTick& tick) const {
  if (tick.cycle < 0) return;
  const std::vector<int>& cycles = scene_.outputs.vtk_cycles;
  if (std::find(cycles.begin(), cycles.end(), tick.cycle) == cycles.end()) return;
  const std::string k = std::to_string(tick.cycle);
  if (tick.ends.heating) write(world, "cycle" + k + "_end_heating");
  if (tick.ends.cooling) write(world, "cycle" + k + "_end_cooling");
}

void VtkSnapshots::write(const World& world, const std::string& tag) const {
  if (out_dir_.empty()) return;
  const std::string dir = out_dir_ + "/vtk";
  std::filesystem::create_directories(dir);
  const SceneDef& s = world.scene();
  const State& st = world.state();
  std::vector<VtkBody> bodies;
  PlacedBody placed;
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    place_body(s, st, static_cast<int>(i), placed);
    VtkBody vb;
    vb.id = static_cast<int>(i);
    vb.velocity = st.v[i];
    // The VTK file draws a sphere as a glyph at its centre, a polyhedron as its faces.
    vb.sphere_radius = placed.sphere_radius;
    if (placed.faces != nullptr) {
      vb.vertices = placed.points;
      vb.faces = *placed.faces;
    } else {
      vb.vertices.push_back(st.x[i]);
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

}  // namespace ratchet
