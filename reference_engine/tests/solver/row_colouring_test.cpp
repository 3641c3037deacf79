// The colouring of the parallel sweep: a permutation of the rows, pairs kept together,
// and no moving body in two groups of one colour (what makes the sweep's result the
// same for any thread count); walls and fixed bodies do not constrain it.
#include "ratchet/solver/row_colouring.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "ratchet/core/random.hpp"

namespace ratchet {
namespace {

struct Rows {
  std::vector<int> a, b;
  void pair(int i, int j, int points) {
    for (int k = 0; k < points; ++k) { a.push_back(i); b.push_back(j); }
  }
};

// Checks every property of a colouring of `rows`; returns the number of colours.
int check(const Rows& rows, const std::vector<bool>& moving) {
  std::vector<int> perm;
  RowColouring col;
  colour_rows(rows.a, rows.b, moving, perm, col);
  std::vector<int> sorted = perm;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t k = 0; k < sorted.size(); ++k) EXPECT_EQ(sorted[k], static_cast<int>(k));
  EXPECT_EQ(col.group_begin.front(), 0);
  EXPECT_EQ(col.group_begin.back(), static_cast<int>(perm.size()));
  EXPECT_EQ(col.colour_begin.front(), 0);
  EXPECT_EQ(col.colour_begin.back(), col.groups());
  for (int c = 0; c < col.colours(); ++c) {
    std::set<int> bodies;
    for (int g = col.colour_begin[static_cast<std::size_t>(c)]; g < col.colour_begin[static_cast<std::size_t>(c) + 1]; ++g) {
      std::set<int> in_group;
      for (int k = col.group_begin[static_cast<std::size_t>(g)]; k < col.group_begin[static_cast<std::size_t>(g) + 1]; ++k) {
        const int r = perm[static_cast<std::size_t>(k)];
        for (int body : {rows.a[static_cast<std::size_t>(r)], rows.b[static_cast<std::size_t>(r)]})
          if (body >= 0 && moving[static_cast<std::size_t>(body)]) in_group.insert(body);
      }
      for (int body : in_group) EXPECT_TRUE(bodies.insert(body).second) << "body " << body << " twice in colour " << c;
    }
  }
  return col.colours();
}

TEST(RowColouring, PairsStayTogetherAndColoursShareNoMovingBody) {
  Rng rng(4);
  Rows rows;
  const int n = 300;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < std::min(n, i + 8); ++j)
      if (uniform(rng, 0.0, 1.0) < 0.6) rows.pair(i, j, 1 + static_cast<int>(uniform(rng, 0.0, 3.99)));
  for (int i = 0; i < n; i += 3) rows.pair(i, -1 - (i % 5), 3);  // walls
  const int colours = check(rows, std::vector<bool>(n, true));
  EXPECT_GT(colours, 4);   // neighbours of up to 14 pairs need several colours...
  EXPECT_LT(colours, 20);  // ...and greedy colouring needs at most degree + 1
}

TEST(RowColouring, WallsAndFixedBodiesDoNotConstrain) {
  // Body 0 touches five walls, fixed body 1 touches bodies 2..5: the walls and body 1
  // tie no groups together; body 0's five wall groups share body 0 itself...
  Rows rows;
  for (int w = 0; w < 5; ++w) rows.pair(0, -1 - w, 2);
  for (int j = 2; j < 6; ++j) rows.pair(1, j, 1);
  std::vector<bool> moving(6, true);
  moving[1] = false;
  EXPECT_EQ(check(rows, moving), 5);
  moving[0] = false;
  EXPECT_EQ(check(rows, moving), 1);  // ...unless it is fixed too
}

TEST(RowColouring, ABodyBeyondTheColourMaskGoesToOneSerialGroup) {
  // A hub touching 200 bodies needs 200 colours; beyond the mask (128) the rest form one
  // group of the last colour, which one thread sweeps in order.
  Rows rows;
  for (int j = 1; j <= 200; ++j) rows.pair(0, j, 1);
  const int colours = check(rows, std::vector<bool>(201, true));
  EXPECT_EQ(colours, 129);
}

}  // namespace
}  // namespace ratchet
