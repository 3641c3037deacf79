#include "ratchet/contact/broad_phase.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace ratchet {

namespace {

// 21 bits per axis, offset so that negative cells pack too.
std::int64_t cell_key(std::int64_t ix, std::int64_t iy, std::int64_t iz) {
  constexpr std::int64_t kOff = 1 << 20;
  return ((ix + kOff) << 42) | ((iy + kOff) << 21) | (iz + kOff);
}

}  // namespace

void find_candidate_pairs(const std::vector<Vec3>& centers, const std::vector<double>& radii, double margin,
                          std::vector<BodyPair>& pairs) {
  pairs.clear();
  const int n = static_cast<int>(centers.size());
  if (n < 2) return;
  const double r_max = *std::max_element(radii.begin(), radii.end());
  const double cell = 2.0 * r_max + margin;
  Vec3 lo = centers[0], hi = centers[0];
  for (const Vec3& c : centers) {
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  std::vector<std::array<std::int64_t, 3>> cells(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Vec3 c = (centers[static_cast<std::size_t>(i)] - lo) / cell;
    cells[static_cast<std::size_t>(i)] = {static_cast<std::int64_t>(std::floor(c.x())),
                                          static_cast<std::int64_t>(std::floor(c.y())),
                                          static_cast<std::int64_t>(std::floor(c.z()))};
  }
  auto test = [&](int i, int j) {
    const std::size_t a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(j);
    if (within_reach(centers[a], centers[b], radii[a], radii[b], margin)) pairs.emplace_back(i, j);
  };
  const Vec3 span = (hi - lo) / cell;
  const double dense_cells = (std::floor(span.x()) + 1.0) * (std::floor(span.y()) + 1.0) * (std::floor(span.z()) + 1.0);
  if (dense_cells <= 8.0 * n + 64.0) {
    // Dense grid over the bodies' bounding box, filled by a counting sort: O(N + cells).
    const std::int64_t nx = static_cast<std::int64_t>(std::floor(span.x())) + 1;
    const std::int64_t ny = static_cast<std::int64_t>(std::floor(span.y())) + 1;
    const std::int64_t nz = static_cast<std::int64_t>(std::floor(span.z())) + 1;
    auto index = [&](std::int64_t x, std::int64_t y, std::int64_t z) { return (z * ny + y) * nx + x; };
    std::vector<int> start(static_cast<std::size_t>(nx * ny * nz + 1), 0), order(static_cast<std::size_t>(n));
    for (const auto& c : cells) ++start[static_cast<std::size_t>(index(c[0], c[1], c[2]) + 1)];
    for (std::size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int i = 0; i < n; ++i) {
      const auto& c = cells[static_cast<std::size_t>(i)];
      order[static_cast<std::size_t>(fill[static_cast<std::size_t>(index(c[0], c[1], c[2]))]++)] = i;
    }
    for (int i = 0; i < n; ++i) {
      const auto& ci = cells[static_cast<std::size_t>(i)];
      for (std::int64_t z = std::max<std::int64_t>(ci[2] - 1, 0); z <= std::min(ci[2] + 1, nz - 1); ++z)
        for (std::int64_t y = std::max<std::int64_t>(ci[1] - 1, 0); y <= std::min(ci[1] + 1, ny - 1); ++y)
          for (std::int64_t x = std::max<std::int64_t>(ci[0] - 1, 0); x <= std::min(ci[0] + 1, nx - 1); ++x) {
            const std::int64_t k = index(x, y, z);
            for (int m = start[static_cast<std::size_t>(k)]; m < start[static_cast<std::size_t>(k + 1)]; ++m) {
              const int j = order[static_cast<std::size_t>(m)];
              if (j > i) test(i, j);
            }
          }
    }
  } else {
    // Sparse bodies (a few far apart): the occupied cells sorted by key, 27 lookups each.
    struct Entry {
      std::int64_t key;
      int body;
      bool operator<(const Entry& o) const { return key < o.key || (key == o.key && body < o.body); }
    };
    std::vector<Entry> entries(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      const auto& c = cells[static_cast<std::size_t>(i)];
      entries[static_cast<std::size_t>(i)] = {cell_key(c[0], c[1], c[2]), i};
    }
    std::sort(entries.begin(), entries.end());
    for (int i = 0; i < n; ++i) {
      const auto& ci = cells[static_cast<std::size_t>(i)];
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            const std::int64_t key = cell_key(ci[0] + dx, ci[1] + dy, ci[2] + dz);
            auto it = std::lower_bound(entries.begin(), entries.end(), Entry{key, i + 1});
            for (; it != entries.end() && it->key == key; ++it) test(i, it->body);
          }
    }
  }
  // Both branches emit the pairs grouped by their first body, in ascending order; only
  // the few partners of each body need sorting, not the whole list.
  for (std::size_t lo_k = 0; lo_k < pairs.size();) {
    std::size_t hi_k = lo_k + 1;
    while (hi_k < pairs.size() && pairs[hi_k].first == pairs[lo_k].first) ++hi_k;
    std::sort(pairs.begin() + static_cast<std::ptrdiff_t>(lo_k), pairs.begin() + static_cast<std::ptrdiff_t>(hi_k));
    lo_k = hi_k;
  }
}

}  // namespace ratchet
