// Reduction of a face-on-face (or face-on-plane) contact region to at most 4 points
// that span it as widely as possible, so that the contact resists rocking.
#pragma once

#include <vector>

#include "ratchet/contact/contact_point.hpp"

namespace ratchet {

// Picks up to 4 of `candidates` (all sharing one normal): the deepest point, the point
// farthest from it in the plane, the point making the largest triangle with those
// two, and the point adding the most area outside that triangle. Ties go to the lower
// index, so the result depends only on the order of the candidates.
void reduce_manifold(const std::vector<ContactPoint>& candidates, ContactManifold& out);

// Up to 4 of `candidates` keeping the support: the points with gap <= touch (those in
// contact) are reduced among themselves as above, and the others (about to close) fill
// the places left, nearest first (stable: ties keep the candidates' order). Reducing all
// together could keep a point well clear of the other body and drop one pressed into
// it. Reorders `candidates`.
void reduce_touching_first(std::vector<ContactPoint>& candidates, double touch, ContactManifold& out);

}  // namespace ratchet
