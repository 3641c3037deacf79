#include "ratchet/contact/pair_list.hpp"

#include <algorithm>
#include <cmath>

namespace ratchet {

namespace {

// The list is searched again once the motion uses half the skin: the other half is a
// wide margin for the rounding of the distances (relative 1e-16).
constexpr double kSkinUsed = 0.5;

}  // namespace

// A pair left out at the search was farther apart than r_i0 + r_j0 + margin + skin. Its
// centres have since come closer by at most |dc_i| + |dc_j| <= 2 D and its radii grown
// by at most 2 G (D, G the largest displacement and growth of any body), so it is still
// out of reach while 2 D + 2 G <= skin.
bool CandidatePairList::holds(const std::vector<Vec3>& centers, const std::vector<double>& radii, double margin,
                              double skin) const {
  if (margin != margin_ || skin != skin_ || centers.size() != centers_.size() || radii.size() != radii_.size())
    return false;
  double d2 = 0.0, grow = 0.0;
  for (std::size_t i = 0; i < centers.size(); ++i) {
    const double dd = (centers[i] - centers_[i]).squaredNorm(), g = radii[i] - radii_[i];
    if (!(dd <= d2)) d2 = dd;  // a NaN is kept, and fails the test below
    if (!(g <= grow)) grow = g;
  }
  return 2.0 * std::sqrt(d2) + 2.0 * grow <= kSkinUsed * skin;
}

const std::vector<BodyPair>& CandidatePairList::mark(const std::vector<Vec3>& centers,
                                                     const std::vector<double>& radii, double margin, double skin,
                                                     std::vector<char>& in_reach) {
  if (!holds(centers, radii, margin, skin)) {
    find_candidate_pairs(centers, radii, margin + skin, kept_);
    centers_ = centers;
    radii_ = radii;
    margin_ = margin;
    skin_ = skin;
    ++searches_;
  }
  in_reach.resize(kept_.size());
  for (std::size_t k = 0; k < kept_.size(); ++k) {
    const std::size_t a = static_cast<std::size_t>(kept_[k].first), b = static_cast<std::size_t>(kept_[k].second);
    in_reach[k] = within_reach(centers[a], centers[b], radii[a], radii[b], margin) ? 1 : 0;
  }
  return kept_;
}

void CandidatePairList::find(const std::vector<Vec3>& centers, const std::vector<double>& radii, double margin,
                             double skin, std::vector<BodyPair>& pairs) {
  std::vector<char> in_reach;
  const std::vector<BodyPair>& candidates = mark(centers, radii, margin, skin, in_reach);
  pairs.clear();
  for (std::size_t k = 0; k < candidates.size(); ++k)
    if (in_reach[k]) pairs.push_back(candidates[k]);
}

}  // namespace ratchet
