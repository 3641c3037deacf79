#include "ratchet/contact/pair_list.hpp"

#include <gtest/gtest.h>

#include "ratchet/core/random.hpp"

namespace ratchet {
namespace {

struct Bodies {
  std::vector<Vec3> c;
  std::vector<double> r;
};

Bodies random_bed(Rng& rng, int n) {
  Bodies b;
  for (int i = 0; i < n; ++i) {
    b.c.emplace_back(uniform(rng, -5, 5), uniform(rng, -5, 5), uniform(rng, 0, 8));
    b.r.push_back(uniform(rng, 0.5, 1.0));
  }
  return b;
}

// Every step, the kept list gives exactly the grid search's pairs, in its order, while
// the bodies drift, grow and shrink; and it searches far less often than every step.
TEST(CandidatePairList, GivesTheGridSearchPairsAtEveryStep) {
  Rng rng(21);
  Bodies b = random_bed(rng, 600);
  CandidatePairList list;
  std::vector<BodyPair> kept, direct;
  const double margin = 0.05, skin = 0.1;
  const int steps = 400;
  for (int step = 0; step < steps; ++step) {
    for (std::size_t i = 0; i < b.c.size(); ++i) {
      b.c[i] += Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)) * 2e-3;
      b.r[i] *= step < steps / 2 ? 1.0 + 2e-5 : 1.0 - 2e-5;  // heating, then cooling
    }
    list.find(b.c, b.r, margin, skin, kept);
    find_candidate_pairs(b.c, b.r, margin, direct);
    ASSERT_EQ(kept, direct) << "step " << step;
  }
  EXPECT_GT(list.searches(), 1);           // the drift used up the skin: searched again
  EXPECT_LT(list.searches(), steps / 5);   // about every 10 steps at 0.0035 per step
}

// mark() gives the candidates and which are in reach: the marked ones are the grid
// search's pairs, and the candidates change only at a search (detection keeps its
// per-pair data aligned with them, world/detect.cpp).
TEST(CandidatePairList, MarksThePairsAmongCandidatesThatChangeOnlyAtASearch) {
  Rng rng(23);
  Bodies b = random_bed(rng, 400);
  CandidatePairList list;
  std::vector<char> in_reach;
  std::vector<BodyPair> last, direct;
  long long searches = 0;
  for (int step = 0; step < 100; ++step) {
    for (std::size_t i = 0; i < b.c.size(); ++i)
      b.c[i] += Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)) * 2e-3;
    const std::vector<BodyPair>& candidates = list.mark(b.c, b.r, 0.05, 0.1, in_reach);
    ASSERT_EQ(in_reach.size(), candidates.size());
    std::vector<BodyPair> marked;
    for (std::size_t k = 0; k < candidates.size(); ++k)
      if (in_reach[k]) marked.push_back(candidates[k]);
    find_candidate_pairs(b.c, b.r, 0.05, direct);
    ASSERT_EQ(marked, direct) << "step " << step;
    if (list.searches() == searches) {
      ASSERT_EQ(candidates, last) << "step " << step;
    }
    searches = list.searches();
    last = candidates;
  }
  EXPECT_GT(list.searches(), 1);
}

// Pairs just outside the reach at the search, brought into it by the motion the skin
// allows: the worst case of the bound (two bodies moving straight at each other).
TEST(CandidatePairList, FindsPairsThatCloseInFromTheSkin) {
  std::vector<Vec3> c = {Vec3(0, 0, 0), Vec3(2.0 + 0.05 + 0.04, 0, 0)};  // gap 0.04 beyond the margin
  std::vector<double> r = {1.0, 1.0};
  CandidatePairList list;
  std::vector<BodyPair> pairs;
  list.find(c, r, 0.05, 0.1, pairs);
  EXPECT_TRUE(pairs.empty());
  for (int k = 0; k < 20; ++k) {  // each closes 0.0011 per step, 0.044 in all: in reach from step 18
    c[0].x() += 0.0011;
    c[1].x() -= 0.0011;
    list.find(c, r, 0.05, 0.1, pairs);
    std::vector<BodyPair> direct;
    find_candidate_pairs(c, r, 0.05, direct);
    ASSERT_EQ(pairs, direct) << "step " << k;
  }
  EXPECT_EQ(pairs, std::vector<BodyPair>{BodyPair(0, 1)});
}

// A jump, another margin or another body count is searched anew.
TEST(CandidatePairList, SearchesAgainWhenTheListCannotHold) {
  Rng rng(22);
  Bodies b = random_bed(rng, 100);
  CandidatePairList list;
  std::vector<BodyPair> pairs, direct;
  list.find(b.c, b.r, 0.05, 0.1, pairs);
  list.find(b.c, b.r, 0.05, 0.1, pairs);
  EXPECT_EQ(list.searches(), 1);
  b.c[7].x() += 0.03;  // 2 x 0.03 > half the skin
  list.find(b.c, b.r, 0.05, 0.1, pairs);
  EXPECT_EQ(list.searches(), 2);
  list.find(b.c, b.r, 0.06, 0.1, pairs);
  EXPECT_EQ(list.searches(), 3);
  find_candidate_pairs(b.c, b.r, 0.06, direct);
  EXPECT_EQ(pairs, direct);
  b.c.emplace_back(0, 0, 4);
  b.r.push_back(0.7);
  list.find(b.c, b.r, 0.06, 0.1, pairs);
  EXPECT_EQ(list.searches(), 4);
  find_candidate_pairs(b.c, b.r, 0.06, direct);
  EXPECT_EQ(pairs, direct);
}

}  // namespace
}  // namespace ratchet
