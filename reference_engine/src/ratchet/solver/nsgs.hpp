// The global contact solve of one step: non-linear Gauss-Seidel over contact points
// with the exact local Coulomb solve (Jean 1999, "The non-smooth contact dynamics
// method", CMAME 177, s. 4; Moreau 1994). Its interface is narrow on purpose:
// solver rows (frames, lever-arm operators, Delassus blocks, biases) and the body
// velocities in; impulses, sweep count and residual out. docs/method.md s. 7.
#pragma once

#include <cstdint>
#include <vector>

#include "ratchet/solver/row_colouring.hpp"
#include "ratchet/solver/solver_rows.hpp"

namespace ratchet {

// Upper bound of solver.anderson_depth (sweeps): AndersonMixer sizes fixed arrays with
// it; 10 and 20 measured no better than the default 5 (docs/scene-format.md).
constexpr int kMaxAndersonDepth = 50;

struct NsgsSettings {
  double tolerance = 1e-4;
  int max_iterations = 100;
  bool by_velocity = false;  // solver.criterion: velocity (else impulse)
  bool friction = true;
  bool rotation = true;
  int anderson_depth = 0;    // > 0: Anderson acceleration with this memory (solver/anderson.hpp)
  int parallel_min_rows = kParallelMinRows;
  const RowColouring* colouring = nullptr;  // the rows' colouring (parallel sweep), or null: one thread in row order
};

struct NsgsResult {
  int sweeps = 0;
  double residual = 0.0;
  bool converged = true;
  bool normal_growth = false;          // unconverged, and the normal impulses still grew
  std::int64_t tangential_solves = 0;  // local solves with friction in this call
  int restarts = 0;                    // Anderson history restarts
  bool plain_fallback = false;         // the acceleration stalled and plain sweeps finished
};

// Sweeps the rows in order until the residual falls below the tolerance or
// max_iterations sweeps have run; rows' lambda hold the start (warm) impulses, already
// applied to the bodies, and the final ones on return.
NsgsResult solve_nsgs(std::vector<SolverRow>& rows, SolverBodies& bodies, const NsgsSettings& settings,
                        SolverScratch& scratch);

}  // namespace ratchet
