#include "ratchet/contact/broad_phase.hpp"

#include <gtest/gtest.h>

#include "ratchet/core/random.hpp"

namespace ratchet {
namespace {

TEST(BroadPhase, FindsExactlyThePairsABruteForceFinds) {
  Rng rng(4);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 50 + 40 * trial;
    std::vector<Vec3> c;
    std::vector<double> r;
    for (int i = 0; i < n; ++i) {
      c.emplace_back(uniform(rng, -8, 8), uniform(rng, -8, 8), uniform(rng, -3, 10));
      r.push_back(uniform(rng, 0.2, 1.0));
    }
    const double margin = 0.1;
    std::vector<BodyPair> pairs, brute;
    find_candidate_pairs(c, r, margin, pairs);
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        if ((c[i] - c[j]).norm() <= r[i] + r[j] + margin) brute.emplace_back(i, j);
    EXPECT_EQ(pairs, brute);  // same pairs, same (sorted) order
  }
}

}  // namespace
}  // namespace ratchet
