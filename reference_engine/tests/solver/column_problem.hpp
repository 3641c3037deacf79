// A test problem for the global solve: a column of n unit masses stacked on a floor,
// each pressing on the one below with the free velocity -g h, frictionless, no
// rotation. The exact impulses are lambda_k = (n - k) g h (contact k under body k, the
// floor contact first): the load of everything above. Gauss-Seidel carries it down
// about one contact per sweep, the slow mode of a deep bed.
#pragma once

#include <vector>

#include "ratchet/solver/nsgs.hpp"

namespace ratchet::test {

struct Column {
  int n = 0;
  double gh = 0.0;
  std::vector<Vec3> v, w;
  std::vector<double> inv_mass, mass, scale;
  std::vector<Mat3> inv_inertia, R;
  std::vector<Vec3> inertia;
  std::vector<SolverRow> rows;
  SolverScratch scratch;

  Column(int count, double g_h, double mu) : n(count), gh(g_h) {
    const std::size_t m = static_cast<std::size_t>(n);
    v.assign(m, Vec3(0.0, 0.0, -gh));
    w.assign(m, Vec3::Zero());
    inv_mass.assign(m, 1.0);
    mass.assign(m, 1.0);
    scale.assign(m, 1.0);
    inv_inertia.assign(m, Mat3::Zero());
    R.assign(m, Mat3::Identity());
    inertia.assign(m, Vec3::Ones());
    for (int k = 0; k < n; ++k) {
      SolverRow r;
      r.a = k;
      r.b = k == 0 ? wall_side(0) : k - 1;  // body k on the floor or on body k - 1
      r.F = Mat3::Identity();               // n = z: columns (z, x, y) would do too
      r.F.col(0) = Vec3::UnitZ();
      r.F.col(1) = Vec3::UnitX();
      r.F.col(2) = Vec3::UnitY();
      const double wnn = k == 0 ? 1.0 : 2.0;
      r.W = wnn * Mat3::Identity();
      r.W_inv = r.W.inverse();
      r.mu = mu;
      rows.push_back(r);
    }
    scratch.v_free = v;
    scratch.w_free = w;
  }

  SolverBodies bodies() { return SolverBodies{v, w, inv_mass, inv_inertia, R, mass, inertia, scale}; }
};

// What the column's solves are asked: no rotation (the column has none), the cap, the
// tolerance, friction or not, and whether the law is the rigid one (its jam tests and
// stall fallback).
inline SolveSettings column_settings(int cap, double tol, bool friction, bool rigid = false) {
  SolveSettings s;
  s.max_iterations = cap;
  s.tolerance = tol;
  s.friction = friction;
  s.rotation = false;
  s.rigid = rigid;
  return s;
}

}  // namespace ratchet::test
