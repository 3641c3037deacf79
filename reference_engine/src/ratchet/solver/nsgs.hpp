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

// solver.method "nsgs". Sweeps the rows in order until the residual falls below the tolerance or
// max_iterations sweeps have run; rows' lambda hold the start (warm) impulses, already
// applied to the bodies, and the final ones on return.
SolveResult solve_nsgs(std::vector<SolverRow>& rows, SolverBodies& bodies, const SolveSettings& settings,
                        SolverScratch& scratch);

}  // namespace ratchet
