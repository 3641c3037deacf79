#include "ratchet/observe/peaks.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace ratchet {

std::vector<CyclePeak> cycle_peaks(const std::vector<double>& t, const std::vector<double>& signal,
                                   double start_time, double cycle_time, int cycles) {
  if (t.size() != signal.size())
    throw std::invalid_argument("cycle_peaks: got " + std::to_string(t.size()) + " times but " +
                                std::to_string(signal.size()) + " values");
  if (!std::isfinite(start_time) || !std::isfinite(cycle_time) || !(cycle_time > 0.0))
    throw std::invalid_argument("cycle_peaks: start time must be finite and cycle time positive");
  if (cycles < 0) throw std::invalid_argument("cycle_peaks: negative cycle count");

  const auto n = static_cast<std::size_t>(cycles);
  std::vector<CyclePeak> best(n);
  std::vector<std::size_t> best_index(n);
  std::vector<char> found(n, 0);
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double ti = t[i], v = signal[i];
    if (!std::isfinite(ti) || std::isnan(v)) continue;
    // Window index from the quotient, then corrected against the exact bounds
    // start + k L <= t < start + (k+1) L so that rounding in the division cannot move
    // a sample lying on a boundary.
    const double q = std::floor((ti - start_time) / cycle_time);
    if (q < -1.0 || q > static_cast<double>(cycles)) continue;
    long k = static_cast<long>(q);
    if (ti < start_time + static_cast<double>(k) * cycle_time) --k;
    else if (ti >= start_time + static_cast<double>(k + 1) * cycle_time) ++k;
    if (k < 0 || k >= cycles) continue;
    const auto ku = static_cast<std::size_t>(k);
    CyclePeak& b = best[ku];
    const bool better = !found[ku] || v > b.value ||
                        (v == b.value && (ti < b.time || (ti == b.time && i < best_index[ku])));
    if (better) {
      b = CyclePeak{static_cast<int>(k), v, ti};
      best_index[ku] = i;
      found[ku] = 1;
    }
  }
  std::vector<CyclePeak> peaks;
  for (std::size_t k = 0; k < n; ++k)
    if (found[k]) peaks.push_back(best[k]);
  return peaks;
}

MeanPeak mean_peak(const std::vector<CyclePeak>& peaks, int first_cycle, int last_cycle) {
  if (first_cycle > last_cycle)
    throw std::invalid_argument("mean_peak: first cycle " + std::to_string(first_cycle) + " is after last cycle " +
                                std::to_string(last_cycle));
  MeanPeak m;
  m.first_cycle = first_cycle;
  m.last_cycle = last_cycle;
  double sum = 0.0;
  for (const CyclePeak& p : peaks)
    if (p.cycle >= first_cycle && p.cycle <= last_cycle) sum += p.value, ++m.count;
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  m.mean = m.count > 0 ? sum / m.count : nan;
  // Two-pass sample variance: no cancellation for peaks that differ little.
  double ss = 0.0;
  for (const CyclePeak& p : peaks)
    if (p.cycle >= first_cycle && p.cycle <= last_cycle) ss += (p.value - m.mean) * (p.value - m.mean);
  m.stddev = m.count > 1 ? std::sqrt(ss / (m.count - 1)) : nan;
  return m;
}

}  // namespace ratchet
