// Snapshots for ParaView (docs/output-format.md, "VTK files"; paper Fig. 4): VTK XML
// PolyData files (.vtp), one piece, the data arrays zlib-compressed binary or ASCII
// (observe/vtk_xml.hpp). Every file carries the field data TimeValue (the simulated
// time, which ParaView shows as the time of the file) and step. Written atomically
// (PATH.partial, then rename; io/atomic_file.hpp). Plain data, no World.
//
// Each writer validates all of its input first, so bad input leaves no file behind:
// std::invalid_argument for invalid or non-finite data, std::runtime_error on I/O
// failure (nothing is left under path or path.partial).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ratchet/core/types.hpp"
#include "ratchet/observe/container_mesh.hpp"
#include "ratchet/observe/vtk_xml.hpp"

namespace ratchet {

// One body. A polyhedron gives its world vertices and faces (indices into vertices,
// each face >= 3 of them, counter-clockwise seen from outside); a sphere gives exactly
// one vertex, its centre, no faces, and sphere_radius > 0.
struct VtkBody {
  int id = 0;
  Vec3 velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();  // world frame
  double scale = 1.0;                    // thermal scale of the body (s_p, or 1 for a fixed body)
  std::vector<Vec3> vertices;
  std::vector<std::vector<int>> faces;
  double sphere_radius = 0.0;  // > 0 marks a sphere
  double volume = 0.0;         // at the current scale
};

// Particle shapes: every sphere a Verts cell at its centre, every face of every
// polyhedron a Polys cell (cells numbered Verts first, then Polys, as VTK numbers them).
// PointData: body_id (Int32), radius (the sphere radius at a sphere's centre, 0 at
// polyhedron vertices; for ParaView's Glyph filter), velocity, angular_velocity (3
// components), scale, volume and equivalent_radius (of the sphere of that volume) of the
// point's body. CellData: the same of the cell's body but radius.
void write_particles_vtp(const std::string& path, const std::vector<VtkBody>& bodies, const VtkTime& time,
                        VtkEncoding encoding = VtkEncoding::Binary);

// One contact point: its position, the normal (unit, from B towards A), the forces on
// A (impulse / h), the gap and the bodies (body_b < 0: wall -1 - body_b).
struct VtkContact {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
  Vec3 normal_force = Vec3::Zero();
  Vec3 tangential_force = Vec3::Zero();
  double gap = 0.0;
  int body_a = 0;
  int body_b = -1;
  Vec3 from = Vec3::Zero();  // A's centre
  Vec3 to = Vec3::Zero();    // B's centre, or the contact point when B is a wall
  int status = 0;            // kContactOpen, kContactStick or kContactSlip
};

// A contact's state after the solve, as DEM viewers colour force chains.
constexpr int kContactOpen = 0;   // no normal force
constexpr int kContactStick = 1;  // inside the friction cone
constexpr int kContactSlip = 2;   // on the cone: |f_t| = mu f_n to round-off

// Contacts as points: one Verts cell per contact at its point. PointData: normal,
// normal_force, tangential_force (3 components), normal_force_magnitude (the signed
// normal force n . normal_force, >= 0 from the solver), gap (Float64), body_a, body_b
// (Int32).
void write_contacts_vtp(const std::string& path, const std::vector<VtkContact>& contacts, const VtkTime& time,
                       VtkEncoding encoding = VtkEncoding::Binary);

// Force chains: one Lines cell per contact, from A's centre to B's (or to the contact
// point on a wall), two points per line. CellData: normal_force (n . normal_force),
// tangential_force (its magnitude; Float64), status (Int32: 0 open, 1 stick, 2 slip),
// body_a, body_b (Int32).
void write_force_chains_vtp(const std::string& path, const std::vector<VtkContact>& contacts, const VtkTime& time,
                           VtkEncoding encoding = VtkEncoding::Binary);

// Container walls: one Polys cell per polygon of the mesh (observe/container_mesh.hpp).
// CellData: wall_index (Int32, index into the scene's walls), side_id (Int32, the
// contacts' body_b of that wall: -1 - wall_index), normal (the wall's unit normal, into
// the container) and normal_force (the wall's total normal force; Float64).
// `normal` and `normal_force` give one entry per polygon.
void write_container_vtp(const std::string& path, const ContainerMesh& mesh, const std::vector<Vec3>& normal,
                         const std::vector<double>& normal_force, const VtkTime& time,
                         VtkEncoding encoding = VtkEncoding::Binary);

}  // namespace ratchet
