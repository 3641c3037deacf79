// The list of accumulators a run has (run/accumulator.hpp), one registration each: a
// new per-cycle observable is its measurement in observe/, its accumulator here in
// run/, and one line in accumulators.cpp (a test's, one ScopedAccumulator). The list's
// order is the order of the columns in timeseries.csv and cycles.csv.
#pragma once

#include <memory>
#include <type_traits>
#include <vector>

#include "ratchet/run/accumulator.hpp"

namespace ratchet {

using AccumulatorFactory = std::unique_ptr<Accumulator> (*)(const ObserverSetup& setup);

struct AccumulatorEntry {
  const char* key;  // its record's name in a checkpoint; nullptr: it keeps none
  AccumulatorFactory make;
};

// The engine's accumulators, then those of the ScopedAccumulators alive.
const std::vector<AccumulatorEntry>& accumulator_entries();

// Adds an accumulator to the runs made while the guard lives and takes it out when the
// guard goes: a test's throwaway observable reaches no other run of its test program.
class ScopedAccumulator {
 public:
  explicit ScopedAccumulator(const AccumulatorEntry& entry);
  ~ScopedAccumulator();
  ScopedAccumulator(const ScopedAccumulator&) = delete;
  ScopedAccumulator& operator=(const ScopedAccumulator&) = delete;

 private:
  AccumulatorEntry entry_;
};

// The guard for an accumulator A made from the setup, or default-constructed.
template <class A>
ScopedAccumulator scoped_accumulator(const char* key) {
  return ScopedAccumulator({key, [](const ObserverSetup& setup) -> std::unique_ptr<Accumulator> {
                              if constexpr (std::is_constructible_v<A, const ObserverSetup&>)
                                return std::make_unique<A>(setup);
                              else
                                return std::make_unique<A>();
                            }});
}

}  // namespace ratchet
