// Per-step scratch: rebuilt from SceneDef + State at every step, never carried over
// (the third kind of data next to scene/scene.hpp and world/state.hpp).
#pragma once

#include <vector>

#include "ratchet/contact/broad_phase.hpp"
#include "ratchet/contact/collide.hpp"
#include "ratchet/contact/common_plane.hpp"
#include "ratchet/contact/contact_point.hpp"
#include "ratchet/contact/manifold_reuse.hpp"
#include "ratchet/contact/pair_list.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/solver/nsgs.hpp"
#include "ratchet/thermal/thermal_protocol.hpp"

namespace ratchet {

// One contact point: what detection found and what the solver ended with (lambda),
// read by the observers. Local frame columns (n, t1, t2).
struct SolverContact {
  int a = 0, b = 0;                // b may name a wall (core/contact_side.hpp)
  ContactPoint geometry;
  Vec3 t1 = Vec3::UnitX(), t2 = Vec3::UnitY();
  Vec3 ra = Vec3::Zero(), rb = Vec3::Zero();  // lever arms from the centres of mass
  double mu = 0.0;
  Vec3 u_expansion = Vec3::Zero(); // relative velocity of the contact from thermal expansion (world)
  Vec3 lambda = Vec3::Zero();      // local impulse (n, t1, t2) on A, after the solve
};

// One replayed pair compared with a fresh build (world/test_hooks.hpp, ReuseAudit).
struct PairAudit {
  bool compared = false, empty_violation = false;
  double error = 0.0, per_motion = 0.0;
};

// Where a gathered contact comes from: manifold >= 0 a candidate pair's slot, -1 - k wall
// pair k; point, its index in that manifold.
struct GatheredFrom {
  int manifold = 0, point = 0;
};

// What became of a candidate pair's kept manifold in a step (solver.manifold_reuse).
enum PairFate : char { kNotKept = 0, kReplayed = 1, kBuilt = 2 };

struct StepScratch {
  ThermalScales next;              // scales at t + h
  double eps_p = 0.0, eps_c = 0.0; // expansion rates (ds/dt)/s over the step
  std::vector<Vec3> v_begin, w_begin;
  std::vector<Mat3> R;             // body -> world rotations
  std::vector<Mat3> inv_inertia;   // world-frame inverse inertia (zero: no rotation)
  std::vector<double> inv_mass;    // zero for fixed bodies
  std::vector<double> scale;       // thermal scale per body (s_p, or 1 for a fixed body)
  std::vector<int> vertex_offset;  // into world_vertices, -1 for spheres
  std::vector<Vec3> world_vertices;
  std::vector<CollisionBody> placed;  // per body, as the narrow phase sees it (points into world_vertices)
  std::vector<Vec3> centers;
  std::vector<double> radii;       // current bounding radii
  // Kept from step to step, unlike the rest: the broad phase's wider list, which only
  // saves grid searches (the pairs are the same with or without it).
  CandidatePairList pair_list;
  double pair_skin = -1.0;         // its skin (world/detect.cpp), set at the first step
  const std::vector<BodyPair>* candidates = nullptr;  // this step's candidate pairs (pair_list's)
  bool slots_aligned = false;      // the state's planes and manifolds are one per candidate (World::align_pair_slots)
  long long slots_search = -1;     // at the pair list's search of this number
  std::vector<char> in_reach;      // per candidate: within reach now (the step's pairs)
  std::vector<ContactManifold> pair_manifolds;  // per candidate (empty out of reach)
  std::vector<char> pair_fate;     // per candidate: its kept manifold this step (PairFate)
  bool audit_on = false;                        // test hook: replayed pairs compared with fresh builds
  std::vector<PairAudit> pair_audit;
  std::vector<std::pair<int, int>> wall_pairs;  // (body, wall) within reach, body-major
  std::vector<ContactManifold> wall_manifolds;  // per wall pair
  std::vector<SolverContact> contacts;   // in the order of `colouring`
  std::vector<int> kept_impulse;   // per contact as gathered: its kept impulse in the state, or -1
  std::vector<GatheredFrom> gathered_from;  // per contact as gathered (before the colour order): its manifold point
  RowColouring colouring;          // the contacts' groups and colours (solver/row_colouring.hpp)
  std::vector<int> order, row_a, row_b;  // the colour order and its input
  std::vector<bool> moving;        // per body: not fixed
  std::vector<SolverRow> rows;     // the solver's data, one per contact, same order
  SolverScratch solver;            // what the global solve keeps between sweeps
};

}  // namespace ratchet
