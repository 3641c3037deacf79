// The list of accumulators a run has (run/accumulator.hpp), one registration each: a
// new per-cycle observable is its measurement in observe/, its accumulator here in
// run/, and one line in accumulators.cpp. The list's order is the order of the columns
// in timeseries.csv and cycles.csv.
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

// The engine's accumulators, then those registered.
const std::vector<AccumulatorEntry>& accumulator_entries();

// Appends an accumulator to every run of this program (from a static initializer: a
// test's throwaway observable). Returns true.
bool register_accumulator(const AccumulatorEntry& entry);

// The same for an accumulator A made from the setup, or default-constructed.
template <class A>
bool register_accumulator(const char* key) {
  return register_accumulator({key, [](const ObserverSetup& setup) -> std::unique_ptr<Accumulator> {
                                 if constexpr (std::is_constructible_v<A, const ObserverSetup&>)
                                   return std::make_unique<A>(setup);
                                 else
                                   return std::make_unique<A>();
                               }});
}

}  // namespace ratchet
