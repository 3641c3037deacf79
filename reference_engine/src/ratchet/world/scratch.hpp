// Per-step scratch: rebuilt from SceneDef + State at every step, never carried over
// (the third kind of data next to scene/scene.hpp and world/state.hpp).
#pragma once

#include <vector>

#include "ratchet/contact/broad_phase.hpp"
#include "ratchet/contact/common_plane.hpp"
#include "ratchet/contact/contact_point.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/thermal/thermal_protocol.hpp"

namespace ratchet {

// One contact point: what detection found and what the solver ended with (lambda),
// read by the observers. Local frame columns (n, t1, t2).
struct SolverContact {
  int a = 0, b = 0;                // b < 0: wall -1 - b
  ContactPoint geometry;
  Vec3 t1 = Vec3::UnitX(), t2 = Vec3::UnitY();
  Vec3 ra = Vec3::Zero(), rb = Vec3::Zero();  // lever arms from the centres of mass
  double mu = 0.0;
  Vec3 u_expansion = Vec3::Zero(); // relative velocity of the contact from thermal expansion (world)
  Vec3 lambda = Vec3::Zero();      // local impulse (n, t1, t2) on A, after the solve
};

// What one local solve of the sweep reads and writes, packed in its own array (hot
// data; SolverContact holds the rest): the operators are built once per step
// (build_solver_contacts) so that a local solve is a few 3x3 products,
// u = F^T (v_a - v_b) + J_a w_a - J_b w_b + u0 and, for an impulse change d,
// v_a += m_a^-1 F d, w_a += I_a^-1 J_a^T d (and minus for B). 432 bytes against 760 for
// the whole record: a bed of 2000 has 8500 contacts, and the sweep streams them all.
struct SolverRow {
  int a = 0, b = 0;                // as in SolverContact
  Mat3 F = Mat3::Identity();       // columns n, t1, t2 (world)
  Mat3 Ja = Mat3::Zero(), Jb = Mat3::Zero();  // rows r x e_k: angular velocity -> local velocity
  Mat3 W = Mat3::Zero();           // local Delassus block W = H^T M^-1 H (only W(0,0) without friction)
  Mat3 W_inv = Mat3::Zero();       // its inverse (the stick solution), with friction only
  double mu = 0.0;
  double bias = 0.0;               // b: u_n + b >= 0 is the velocity form of g(t+h) >= 0
  Vec3 u0 = Vec3::Zero();          // F^T u_expansion: the local velocity no body velocity explains
  Vec3 lambda = Vec3::Zero();      // local impulse (n, t1, t2) on A
};

struct StepScratch {
  ThermalScales next;              // scales at t + h
  double eps_p = 0.0, eps_c = 0.0; // expansion rates (ds/dt)/s over the step
  std::vector<Vec3> v_begin, w_begin;
  std::vector<Mat3> R;             // body -> world rotations
  std::vector<Mat3> inv_inertia;   // world-frame inverse inertia (zero: no rotation)
  std::vector<double> inv_mass;    // zero for fixed bodies
  std::vector<int> vertex_offset;  // into world_vertices, -1 for spheres
  std::vector<Vec3> world_vertices;
  std::vector<Vec3> centers;
  std::vector<double> radii;       // current bounding radii
  std::vector<BodyPair> pairs;
  std::vector<ContactManifold> pair_manifolds;
  std::vector<CommonPlaneCache> pair_planes;    // per candidate pair (polyhedron pairs only)
  std::vector<std::pair<int, int>> wall_pairs;  // (body, wall) within reach, body-major
  std::vector<ContactManifold> wall_manifolds;  // per wall pair
  std::vector<SolverContact> contacts;
  std::vector<SolverRow> rows;     // the sweep's data, one per contact, same order
  // Criterion::Velocity: body velocities before the contact impulses and before the sweep.
  std::vector<Vec3> v_free, w_free, v_sweep, w_sweep;
};

}  // namespace ratchet
