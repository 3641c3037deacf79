// A fixed partition of a step's contact rows for a parallel Gauss-Seidel sweep whose
// result does not depend on the number of threads: rows are grouped by body pair (the
// points of one manifold, solved in order by one thread), and groups are coloured so
// that no two groups of a colour share a moving body. The sweep visits the colours in
// order; within a colour the groups touch disjoint bodies, so any split among threads
// performs exactly the arithmetic of one thread visiting them in order (the coloured
// Gauss-Seidel of graph-coloured solvers, e.g. Box2D v3's solver sets; Tonge, Benevolenski
// & Voroshilov 2012, "Mass splitting for jitter-free parallel rigid body simulation",
// SIGGRAPH, s. 3 on colouring). The colouring is greedy in the contacts' gather order,
// so it is a function of the contact list alone.
#pragma once

#include <vector>

namespace ratchet {

struct RowColouring {
  std::vector<int> group_begin;   // rows [group_begin[g], group_begin[g + 1]) are group g
  std::vector<int> colour_begin;  // groups [colour_begin[c], colour_begin[c + 1]) share no moving body
  int groups() const { return group_begin.empty() ? 0 : static_cast<int>(group_begin.size()) - 1; }
  int colours() const { return colour_begin.empty() ? 0 : static_cast<int>(colour_begin.size()) - 1; }
};

// Colours the rows of bodies a[k], b[k] (b < 0 a wall; moving[i] false for a fixed body,
// whose velocity no row changes). Rows of one pair must be consecutive. Writes the order
// `perm` (perm[j] = the input row that goes to place j: colours in order, groups in input
// order within a colour) and the colouring of the permuted rows.
void colour_rows(const std::vector<int>& a, const std::vector<int>& b, const std::vector<bool>& moving,
                 std::vector<int>& perm, RowColouring& out);

}  // namespace ratchet
