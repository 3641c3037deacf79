// Passes split among threads give the same bits for any thread count: every item is
// visited once, and a sum is the blocks' partial sums (item order within a block) added
// in block order, whatever the threads.
#include "ratchet/solver/fixed_order_passes.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace ratchet {
namespace {

// Terms whose sum depends on the order it is taken in: magnitudes from 1e-8 to 1e8.
std::vector<double> terms(int n) {
  std::vector<double> t;
  for (int k = 0; k < n; ++k) t.push_back(std::pow(10.0, (k * 7919) % 17 - 8) * (k % 3 == 0 ? -1.0 : 1.0));
  return t;
}

TEST(FixedOrderPasses, SumsAreTheBlocksInOrderOnAnyNumberOfThreads) {
  const int saved_threads = omp_get_max_threads();
  const int n = 10 * FixedOrderPasses::kBlock + 37;  // a short last block
  const std::vector<double> t = terms(n);
  double by_blocks = 0.0, in_item_order = 0.0;
  for (int b = 0; b * FixedOrderPasses::kBlock < n; ++b) {
    double s = 0.0;
    for (int k = b * FixedOrderPasses::kBlock; k < std::min(n, (b + 1) * FixedOrderPasses::kBlock); ++k) s += t[static_cast<std::size_t>(k)];
    by_blocks += s;
  }
  for (double x : t) in_item_order += x;
  ASSERT_NE(by_blocks, in_item_order);  // the terms tell the two orders apart
  std::vector<double> partial;
  for (bool parallel : {false, true}) {
    for (int threads : {1, 2, 3, 8}) {
      omp_set_num_threads(threads);
      const FixedOrderPasses pass{parallel, &partial};
      const auto s = pass.sum<2>(n, [&](int k, std::array<double, 2>& acc) {
        acc[0] += t[static_cast<std::size_t>(k)];
        acc[1] += 2.0 * t[static_cast<std::size_t>(k)];
      });
      EXPECT_EQ(s[0], by_blocks) << threads << " threads, parallel " << parallel;
      EXPECT_EQ(s[1], 2.0 * by_blocks) << threads << " threads";  // doubling is exact
      std::vector<int> visits(static_cast<std::size_t>(n), 0);
      pass.for_each(n, [&](int k) { ++visits[static_cast<std::size_t>(k)]; });
      EXPECT_EQ(std::count(visits.begin(), visits.end(), 1), n) << threads << " threads";
    }
  }
  omp_set_num_threads(saved_threads);
}

}  // namespace
}  // namespace ratchet
