// When a run counts a time as reached. t grows step by step (t += h, World::step), so
// after N steps it is off the exact N h by up to N ulp(t): a time that falls on a step
// can be missed by round-off. Both tolerances are in units of the step h, and far below
// one step, so no time moves to another step.
#pragma once

namespace ratchet {

// The start of cycling, the settle stage's time limit (settle.max_time) and the end of
// a pressure block (outputs.pressure_window) count as reached by a state within
// kTimeRoundTol h below them, and a packing may end that much after settle.max_time
// (run/cycle_clock.cpp, run/packing.cpp, run/pressure_peaks.cpp). A time missed by
// more is reached one step later.
constexpr double kTimeRoundTol = 1e-9;

// A stage mark (end of heating, of cooling, of a cycle) counts as reached by a state
// within kStageMarkTol h below it. 17,000 steps of h = 0.004 from t = 20 left the end
// of the last cycle 9e-12 = 2.2e-9 h short, and 1e-9 h missed it (no last cycle-end
// snapshot, no W_rms of the windows ending there). 1e-4 h covers the worst case of the
// paper tier (140,000 steps to t = 560: 2e-6 h) with a margin.
constexpr double kStageMarkTol = 1e-4;

}  // namespace ratchet
