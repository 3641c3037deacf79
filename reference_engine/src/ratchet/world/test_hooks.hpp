// Test-only seams of the step. The planted-regression program (regression/planted_main.cpp)
// sets a hook before it runs the ordinary command line, so the golden comparison can
// be shown to catch a dropped physics term without a second build of the engine. Read
// once per step, outside the sweeps; never set by the ratchet program.
#pragma once

namespace ratchet {

struct TestHooks {
  bool drop_wall_expansion = false;  // contacts with an expanding wall lose its expansion velocity
  int parallel_min_rows = -1;        // >= 0: the solve's parallel loops run above this many rows
                                     // (tests run them on small beds); else kParallelMinRows
};

TestHooks& test_hooks();

}  // namespace ratchet
