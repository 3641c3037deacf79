// Peak pressure per thermal cycle and the mean peak pressure over the steady-state
// cycles, P_max-bar (paper s.3, Fig. 3: "the peak value for each cycle is denoted by
// a dot", "mean peak pressure during the steady state"; docs/output-format.md, "P_max").
// Works on any sampled signal, no World.
#pragma once

#include <vector>

namespace ratchet {

struct CyclePeak {
  int cycle = 0;      // k, window [start + k L, start + (k+1) L)
  double value = 0.0; // maximum of the signal in the window
  double time = 0.0;  // time of the maximum (earliest sample among equal maxima)
};

// Maximum of `signal` within each cycle window [start_time + k cycle_time,
// start_time + (k+1) cycle_time), k = 0 .. cycles-1. A sample exactly at a window's
// end belongs to the next window. On ties the earliest sample wins (lowest index among
// equal times). NaN samples are ignored; a window without any finite sample (a run
// that stopped early) gives no entry, so the result is sorted by cycle and may have
// fewer than `cycles` entries. t need not be sorted.
// Throws std::invalid_argument if t and signal differ in size, cycle_time <= 0,
// cycles < 0, or start_time / cycle_time is not finite.
std::vector<CyclePeak> cycle_peaks(const std::vector<double>& t, const std::vector<double>& signal,
                                   double start_time, double cycle_time, int cycles);

struct MeanPeak {
  double mean = 0.0;    // mean of the peaks with first_cycle <= cycle <= last_cycle
  double stddev = 0.0;  // sample standard deviation (n - 1); NaN if count < 2
  int count = 0;        // peaks in the window
  int first_cycle = 0;  // the window, inclusive, as given
  int last_cycle = 0;
};

// Mean and sample standard deviation of the peaks whose cycle lies in
// [first_cycle, last_cycle] (inclusive): the paper's mean peak pressure over the
// steady-state cycles. mean is NaN if no peak lies in the window.
// Throws std::invalid_argument if first_cycle > last_cycle.
MeanPeak mean_peak(const std::vector<CyclePeak>& peaks, int first_cycle, int last_cycle);

}  // namespace ratchet
