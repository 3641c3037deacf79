#include "ratchet/solver/row_colouring.hpp"

#include <array>
#include <cstdint>

namespace ratchet {

namespace {

// Colours per body tracked in a bit mask; a group that finds none free (a body with more
// than this many contact pairs, far beyond a packing's 10-15) joins the last colour,
// which the sweep visits on one thread.
constexpr int kMaskWords = 2;
constexpr int kMaxColours = 64 * kMaskWords;
using Mask = std::array<std::uint64_t, kMaskWords>;

int lowest_free(const Mask& used) {
  for (int w = 0; w < kMaskWords; ++w)
    if (~used[static_cast<std::size_t>(w)] != 0)
      return 64 * w + __builtin_ctzll(~used[static_cast<std::size_t>(w)]);
  return kMaxColours;  // the serial colour
}

}  // namespace

void colour_rows(const std::vector<int>& a, const std::vector<int>& b, const std::vector<bool>& moving,
                 std::vector<int>& perm, RowColouring& out) {
  const int n = static_cast<int>(a.size());
  // Groups: runs of rows with the same pair.
  std::vector<int> group_start;
  for (int k = 0; k < n; ++k)
    if (k == 0 || a[static_cast<std::size_t>(k)] != a[static_cast<std::size_t>(k - 1)] ||
        b[static_cast<std::size_t>(k)] != b[static_cast<std::size_t>(k - 1)])
      group_start.push_back(k);
  const int ng = static_cast<int>(group_start.size());
  group_start.push_back(n);
  std::vector<Mask> used(moving.size(), Mask{});
  std::vector<int> colour(static_cast<std::size_t>(ng));
  std::vector<int> count(kMaxColours + 1, 0);
  auto moves = [&](int body) { return body >= 0 && moving[static_cast<std::size_t>(body)]; };
  for (int g = 0; g < ng; ++g) {
    const int ia = a[static_cast<std::size_t>(group_start[static_cast<std::size_t>(g)])];
    const int ib = b[static_cast<std::size_t>(group_start[static_cast<std::size_t>(g)])];
    Mask m{};
    for (int w = 0; w < kMaskWords; ++w) {
      if (moves(ia)) m[static_cast<std::size_t>(w)] |= used[static_cast<std::size_t>(ia)][static_cast<std::size_t>(w)];
      if (moves(ib)) m[static_cast<std::size_t>(w)] |= used[static_cast<std::size_t>(ib)][static_cast<std::size_t>(w)];
    }
    const int c = lowest_free(m);
    colour[static_cast<std::size_t>(g)] = c;
    ++count[static_cast<std::size_t>(c)];
    if (c < kMaxColours) {
      const std::uint64_t bit = std::uint64_t{1} << (c % 64);
      if (moves(ia)) used[static_cast<std::size_t>(ia)][static_cast<std::size_t>(c / 64)] |= bit;
      if (moves(ib)) used[static_cast<std::size_t>(ib)][static_cast<std::size_t>(c / 64)] |= bit;
    }
  }
  // Colours in order (empty ones dropped), groups in input order within each.
  std::vector<int> first(kMaxColours + 1, 0);  // first group slot of each colour
  out.colour_begin.assign(1, 0);
  int slot = 0;
  for (int c = 0; c <= kMaxColours; ++c) {
    first[static_cast<std::size_t>(c)] = slot;
    slot += count[static_cast<std::size_t>(c)];
    if (count[static_cast<std::size_t>(c)] > 0) out.colour_begin.push_back(slot);
  }
  if (count[kMaxColours] > 0) {
    // The serial colour: its groups may share bodies, so it becomes one group.
    out.colour_begin.back() = out.colour_begin[out.colour_begin.size() - 2] + 1;
  }
  std::vector<int> group_of_slot(static_cast<std::size_t>(ng));
  for (int g = 0; g < ng; ++g) group_of_slot[static_cast<std::size_t>(first[static_cast<std::size_t>(colour[static_cast<std::size_t>(g)])]++)] = g;
  perm.clear();
  perm.reserve(static_cast<std::size_t>(n));
  out.group_begin.assign(1, 0);
  for (int s = 0; s < ng; ++s) {
    const int g = group_of_slot[static_cast<std::size_t>(s)];
    for (int k = group_start[static_cast<std::size_t>(g)]; k < group_start[static_cast<std::size_t>(g) + 1]; ++k)
      perm.push_back(k);
    const bool serial = colour[static_cast<std::size_t>(g)] == kMaxColours;
    const bool last_of_serial = serial && s + 1 == ng;
    if (!serial || last_of_serial) out.group_begin.push_back(static_cast<int>(perm.size()));
  }
}

}  // namespace ratchet
