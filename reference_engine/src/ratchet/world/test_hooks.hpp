// Test-only seams of the step. The planted-regression program (regression/planted_main.cpp)
// sets a hook before it runs the ordinary command line, so the golden comparison can
// be shown to catch a dropped physics term without a second build of the engine. Read
// once per step, outside the sweeps; never set by the ratchet program.
#pragma once

#include "ratchet/solver/solver_rows.hpp"

namespace ratchet {

// What manifold reuse changed (solver.manifold_reuse): every replayed pair is also built
// anew, and the two compared. Accumulated over the steps run while it is set.
struct ReuseAudit {
  long replayed = 0;           // replayed pairs compared
  long empty_violations = 0;   // replayed empty, but the fresh build found a point
  double max_gap_error = 0.0;  // largest |deepest replayed gap - deepest fresh gap|
  double max_error_per_motion = 0.0;  // ... divided by the pair's motion bound (delta)
};

struct TestHooks {
  bool drop_wall_expansion = false;  // contacts with an expanding wall lose its expansion velocity
  int parallel_min_rows = -1;        // >= 0: the solve's parallel loops run above this many rows
                                     // (tests run them on small beds); else kParallelMinRows
  ReuseAudit* reuse_audit = nullptr;  // set: audit manifold reuse (the bed_trace bench sets it too)
};

TestHooks& test_hooks();

// The step's row count above which its per-row loops run on all threads.
inline int parallel_min_rows() {
  return test_hooks().parallel_min_rows >= 0 ? test_hooks().parallel_min_rows : kParallelMinRows;
}

}  // namespace ratchet
