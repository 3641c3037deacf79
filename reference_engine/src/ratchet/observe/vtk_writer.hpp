// Snapshots for ParaView (docs/output-format.md, "VTK files"; paper Fig. 4): legacy
// ASCII VTK files ("# vtk DataFile Version 3.0", DATASET POLYDATA; format: VTK User's
// Guide, "VTK File Formats", legacy format). Written atomically (PATH.partial, then
// rename; io/atomic_file.hpp). Plain data, no World.
#pragma once

#include <string>
#include <vector>

#include "ratchet/core/types.hpp"

namespace ratchet {

// One body. A polyhedron gives its world vertices and faces (indices into vertices,
// each face >= 3 of them, counter-clockwise seen from outside); a sphere gives exactly
// one vertex, its centre, no faces, and sphere_radius > 0.
struct VtkBody {
  int id = 0;
  Vec3 velocity = Vec3::Zero();
  std::vector<Vec3> vertices;
  std::vector<std::vector<int>> faces;
  double sphere_radius = 0.0;  // > 0 marks a sphere
};

// Particle shapes: every face of every polyhedron is a POLYGONS cell, every sphere a
// VERTICES cell at its centre. CELL_DATA: body_id (int) and velocity (vector) of the
// cell's body. POINT_DATA: radius (sphere radius at a sphere's centre, 0 at polyhedron
// vertices; for ParaView's Glyph filter). Cells are listed VERTICES first, then
// POLYGONS, as the format orders cell data.
// Throws std::invalid_argument for an invalid body (before anything is written),
// std::runtime_error on I/O failure (nothing is left under path or path.partial).
void write_particles_vtk(const std::string& path, const std::vector<VtkBody>& bodies,
                         const std::string& title = "ratchet particles");

// One contact of the force network: a segment from a to b (the two body centres, or a
// body centre and the contact point for a wall contact), its normal force and bodies
// (body_b = -1 for a wall).
struct VtkContact {
  Vec3 a = Vec3::Zero();
  Vec3 b = Vec3::Zero();
  double normal_force = 0.0;
  int body_a = 0;
  int body_b = -1;
};

// Contact force network: one LINES cell per contact, 2 points each. CELL_DATA:
// SCALARS normal_force (double), and FIELD arrays body_a, body_b (int).
// Throws std::invalid_argument for non-finite data, std::runtime_error on I/O failure.
void write_contact_network_vtk(const std::string& path, const std::vector<VtkContact>& contacts,
                               const std::string& title = "ratchet contact network");

}  // namespace ratchet
