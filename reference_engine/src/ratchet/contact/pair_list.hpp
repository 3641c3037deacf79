// The broad phase's pairs kept from step to step (a Verlet neighbour list: Verlet 1967,
// Phys. Rev. 159, 98; Allen & Tildesley, Computer Simulation of Liquids, 1987, s. 5.3.1).
// The grid search (contact/broad_phase.hpp) runs with the reach widened by a skin; later
// steps only test the kept pairs, until the bodies have moved or grown by more than the
// skin allows. The pairs found are those of find_candidate_pairs, in the same order.
#pragma once

#include <vector>

#include "ratchet/contact/broad_phase.hpp"

namespace ratchet {

class CandidatePairList {
 public:
  // The pairs find_candidate_pairs(centers, radii, margin) gives, from the kept list
  // when it still holds every one of them, else from a new grid search with reach
  // margin + skin (skin > 0).
  void find(const std::vector<Vec3>& centers, const std::vector<double>& radii, double margin, double skin,
            std::vector<BodyPair>& pairs);
  // The same search, given as the kept candidates (returned; the list lives until the
  // next call) and, per candidate, whether it is within reach now: find's pairs are the
  // candidates marked 1, in the same order. Detection keeps its per-pair data aligned
  // with the candidates, which change only at a new grid search (world/detect.cpp).
  const std::vector<BodyPair>& mark(const std::vector<Vec3>& centers, const std::vector<double>& radii,
                                    double margin, double skin, std::vector<char>& in_reach);
  long long searches() const { return searches_; }  // grid searches so far

 private:
  bool holds(const std::vector<Vec3>& centers, const std::vector<double>& radii, double margin, double skin) const;

  std::vector<BodyPair> kept_;    // pairs within margin + skin at the last search
  std::vector<Vec3> centers_;     // the centres and radii of that search
  std::vector<double> radii_;
  double margin_ = -1.0, skin_ = 0.0;
  long long searches_ = 0;
};

}  // namespace ratchet
