// Passes over n items (rows or bodies) that may be split among threads without changing a
// bit: each item is written by one thread, and a sum is taken in fixed blocks of kBlock
// items, each block in item order, the blocks' sums then added in block order. The
// blocks do not depend on the thread count, so neither do the sums (Box2D v3 and the
// coloured sweep of solver/nsgs.cpp keep their reductions in a fixed order the same way).
#pragma once

#include <algorithm>
#include <array>
#include <vector>

namespace ratchet {

struct FixedOrderPasses {
  static constexpr int kBlock = 256;  // items per partial sum: a few microseconds of work each
  bool parallel = false;              // split among the threads of a parallel region
  std::vector<double>* partial;       // the blocks' partial sums (scratch)

  template <class F>
  void for_each(int n, F f) const {
#pragma omp parallel for schedule(static) if (parallel)
    for (int k = 0; k < n; ++k) f(k);
  }

  // sum_k f(k, s) into the M sums s, in the fixed order above.
  template <int M, class F>
  std::array<double, M> sum(int n, F f) const {
    const int blocks = (n + kBlock - 1) / kBlock;
    partial->resize(static_cast<std::size_t>(blocks) * M);
    double* part = partial->data();
#pragma omp parallel for schedule(static) if (parallel)
    for (int b = 0; b < blocks; ++b) {
      std::array<double, M> s{};
      const int end = std::min(n, (b + 1) * kBlock);
      for (int k = b * kBlock; k < end; ++k) f(k, s);
      for (int j = 0; j < M; ++j) part[static_cast<std::size_t>(b) * M + j] = s[static_cast<std::size_t>(j)];
    }
    std::array<double, M> total{};
    for (int b = 0; b < blocks; ++b)
      for (int j = 0; j < M; ++j) total[static_cast<std::size_t>(j)] += part[static_cast<std::size_t>(b) * M + j];
    return total;
  }
};

}  // namespace ratchet
