// The rigid law's stall fallback (solver.stall_fallback "apgd"): Coulomb's law solved by
// de Saxcé's fixed point, each of its convex problems by Nesterov's accelerated projected
// gradient with a step found by backtracking and a gradient restart (Mazhar, Heyn,
// Negrut & Tasora 2015, "Using Nesterov's method to accelerate multibody dynamics with
// friction and contact", ACM TOG 34(3):32; de Saxcé & Feng 1991, the bipotential;
// Acary, Brémond & Huber 2018, INRIA RR-9118, for the fixed point and the residual).
// A rigid Gauss-Seidel solve of a squeezed bed can cycle far from the answer until its
// cap (a rigid paper bed: 20,000 sweeps, residual 1e-3); from there the gradient method
// converges (docs/performance.md, "The rigid law's stalled steps"). docs/method.md s. 7.
#pragma once

#include <vector>

#include "ratchet/solver/solver_rows.hpp"

namespace ratchet {

struct ApgdResult {
  int iterations = 0;   // gradient steps, each a pass over the rows' velocities and one over their impulses
  double residual = 0.0;  // Coulomb's natural-map residual, relative (coulomb_residual)
  bool converged = false;
};

// From the rows' impulses (applied to the bodies) to a solution of the rigid law whose
// natural-map residual is below settings.tolerance, in at most max_iterations steps.
// The rows' impulses and the bodies' velocities hold the last iterate on return.
// One thread: the result is the same for any thread count.
ApgdResult solve_apgd(std::vector<SolverRow>& rows, SolverBodies& bodies, const SolveSettings& settings,
                      SolverScratch& scratch, int max_iterations);

// ||lambda - P_K(lambda - rho (u + mu |u_t| n))|| / ||lambda|| (or the norm itself when
// lambda is zero), rho = 1 / W_nn per row, u the rows' local velocity with the bias on
// the normal: zero exactly at a solution of Coulomb's law (de Saxcé's form of it).
double coulomb_residual(const std::vector<SolverRow>& rows, SolverBodies& bodies, bool rotation);

}  // namespace ratchet
