#include "ratchet/contact/broad_phase.hpp"

#include <algorithm>
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
  struct Entry {
    std::int64_t key;
    int body;
    bool operator<(const Entry& o) const { return key < o.key || (key == o.key && body < o.body); }
  };
  std::vector<Entry> entries(static_cast<std::size_t>(n));
  std::vector<std::array<std::int64_t, 3>> cells(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Vec3& c = centers[static_cast<std::size_t>(i)];
    cells[i] = {static_cast<std::int64_t>(std::floor(c.x() / cell)), static_cast<std::int64_t>(std::floor(c.y() / cell)),
                static_cast<std::int64_t>(std::floor(c.z() / cell))};
    entries[i] = {cell_key(cells[i][0], cells[i][1], cells[i][2]), i};
  }
  std::sort(entries.begin(), entries.end());
  for (int i = 0; i < n; ++i) {
    const auto& ci = cells[static_cast<std::size_t>(i)];
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const std::int64_t key = cell_key(ci[0] + dx, ci[1] + dy, ci[2] + dz);
          auto it = std::lower_bound(entries.begin(), entries.end(), Entry{key, i + 1});
          for (; it != entries.end() && it->key == key; ++it) {
            const int j = it->body;
            const double reach = radii[i] + radii[j] + margin;
            if ((centers[i] - centers[j]).squaredNorm() <= reach * reach) pairs.emplace_back(i, j);
          }
        }
  }
  std::sort(pairs.begin(), pairs.end());
}

}  // namespace ratchet
