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

// A few bodies far from the rest make the dense grid over the bounding box too large:
// the sparse (sorted cell) path must find the same pairs.
TEST(BroadPhase, FarOutliersTakeTheSparsePathWithTheSamePairs) {
  Rng rng(5);
  std::vector<Vec3> c;
  std::vector<double> r;
  for (int i = 0; i < 200; ++i) {
    c.emplace_back(uniform(rng, -4, 4), uniform(rng, -4, 4), uniform(rng, 0, 6));
    r.push_back(uniform(rng, 0.3, 0.8));
  }
  c.emplace_back(5000.0, 0.0, 0.0);  // 200 bodies, a box of ~3000 x 5 x 4 cells
  r.push_back(0.5);
  c.emplace_back(5000.5, 0.2, 0.1);
  r.push_back(0.5);
  std::vector<BodyPair> pairs, brute;
  find_candidate_pairs(c, r, 0.05, pairs);
  const int n = static_cast<int>(c.size());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if ((c[i] - c[j]).norm() <= r[i] + r[j] + 0.05) brute.emplace_back(i, j);
  EXPECT_EQ(pairs, brute);
  EXPECT_EQ(pairs.back(), BodyPair(200, 201));  // the outliers touch each other
}

}  // namespace
}  // namespace ratchet
