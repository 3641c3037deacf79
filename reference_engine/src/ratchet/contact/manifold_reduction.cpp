#include "ratchet/contact/manifold_reduction.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace ratchet {

namespace {

// In-plane component of a - b (normal component removed).
Vec3 in_plane(const Vec3& a, const Vec3& b, const Vec3& n) {
  const Vec3 d = a - b;
  return d - n * n.dot(d);
}

}  // namespace

void reduce_manifold(const std::vector<ContactPoint>& candidates, ContactManifold& out) {
  out.count = 0;
  const int m = static_cast<int>(candidates.size());
  if (m <= 4) {
    for (const ContactPoint& c : candidates) out.add(c);
    return;
  }
  const Vec3 n = candidates.front().normal;
  auto best_index = [&](auto&& score) {
    int best = -1;
    double best_score = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < m; ++i) {
      const double s = score(i);
      if (s > best_score) { best_score = s; best = i; }
    }
    return best;
  };
  const int i0 = best_index([&](int i) { return -candidates[i].gap; });
  const Vec3 p0 = candidates[i0].point;
  const int i1 = best_index([&](int i) { return in_plane(candidates[i].point, p0, n).squaredNorm(); });
  const Vec3 p1 = candidates[i1].point;
  // Signed doubled area of triangle (p0, p1, p) about n.
  auto area = [&](const Vec3& a, const Vec3& b, const Vec3& p) {
    return n.dot(in_plane(b, a, n).cross(in_plane(p, a, n)));
  };
  const int i2 = best_index([&](int i) {
    if (i == i0 || i == i1) return -1.0;
    return std::abs(area(p0, p1, candidates[i].point));
  });
  // Orient the triangle counter-clockwise about n; the fourth point is the one that
  // lies farthest outside one of its edges.
  int a = i0, b = i1, c = i2;
  if (area(candidates[a].point, candidates[b].point, candidates[c].point) < 0.0) std::swap(b, c);
  const std::array<int, 3> tri{a, b, c};
  const int i3 = best_index([&](int i) {
    if (i == a || i == b || i == c) return -1.0;
    double added = 0.0;
    for (int e = 0; e < 3; ++e) {
      const Vec3& pa = candidates[tri[e]].point;
      const Vec3& pb = candidates[tri[(e + 1) % 3]].point;
      added = std::max(added, -area(pa, pb, candidates[i].point));
    }
    return added;
  });
  for (int i : {i0, i1, i2}) out.add(candidates[i]);
  if (i3 >= 0 && i3 != i0 && i3 != i1 && i3 != i2) out.add(candidates[i3]);
}

void reduce_touching_first(std::vector<ContactPoint>& candidates, double touch, ContactManifold& out) {
  out.count = 0;
  if (candidates.size() <= 4) {
    for (const ContactPoint& c : candidates) out.add(c);
    return;
  }
  const auto near = std::stable_partition(candidates.begin(), candidates.end(),
                                          [&](const ContactPoint& c) { return c.gap <= touch; });
  if (near - candidates.begin() > 4) {
    candidates.erase(near, candidates.end());
    reduce_manifold(candidates, out);
    return;
  }
  std::stable_sort(near, candidates.end(), [](const ContactPoint& x, const ContactPoint& y) { return x.gap < y.gap; });
  for (std::size_t k = 0; k < 4; ++k) out.add(candidates[k]);
}

}  // namespace ratchet
