// Contact manifolds kept across steps while a pair moves little, in the spirit of the
// body-pair caches of Jolt (BodyPairCache: reuse under a bound on the relative position
// and rotation) and Box2D v3 (contact reuse): a polyhedron pair's manifold is rebuilt
// only when the pair has moved, relative to its pose at the last build, by more than
// `solver.manifold_reuse` (a length). In between its points are replayed as material
// points of both bodies: each point of A and of B moves with its body, the normal with A
// (or with B when it is B's face normal), and the gap is taken between them anew.
//
// The bound (docs/method.md s. 3): every material point of the two bodies has moved, in
// A's frame, by at most
//   delta = |o - o0| + ||R - R0||_F s_B r_B + |s_B - s_B0| r_B + |s_A - s_A0| r_A
// since the build (o, R: B's centre and rotation in A's frame; s: thermal scales; r: the
// shapes' bounding radii). The exact gap of the pair moves by at most delta (a signed
// distance between convex sets is 1-Lipschitz in their motion), so a pair found farther
// than margin + delta apart stays empty, and the deepest replayed point stays within
// about 2 delta of the exact gap (tests/contact/manifold_reuse_test.cpp).
#pragma once

#include <array>
#include <cstdint>

#include "ratchet/contact/common_plane.hpp"
#include "ratchet/contact/contact_point.hpp"
#include "ratchet/contact/polyhedron_view.hpp"

namespace ratchet {

// Pose of B in A's frame, and both scales.
struct PairPose {
  Mat3 rotation = Mat3::Identity();  // R_A^T R_B
  Vec3 offset = Vec3::Zero();        // R_A^T (c_B - c_A)
  double scale_a = 1.0, scale_b = 1.0;
};

PairPose pair_pose(const PolyhedronView& a, const PolyhedronView& b);

// The largest motion of a material point of A or B, in A's frame, from `then` to `now`.
double pair_motion(const PairPose& then, const PairPose& now, double radius_a, double radius_b);

// A pair's manifold as built, in the bodies' shape frames (unscaled), with the pose it
// was built at. An empty manifold keeps a lower bound of the pair's gap instead.
struct KeptManifold {
  int a = 0, b = 0;
  PairPose pose;
  double gap_bound = 0.0;  // count 0: the gap was at least this at the build
  int count = 0;            // points; -1 in the state: no manifold kept (world/state.hpp)
  bool normal_on_b = false;  // the normal is B's face normal: it turns with B
  Vec3 normal = Vec3::Zero();  // in A's frame (or B's when normal_on_b)
  // Material points of A and B, shape frames; the slots past count stay zero (Eigen does
  // not zero a Vec3 by itself, and state files hold all four).
  std::array<Vec3, 4> on_a = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  std::array<Vec3, 4> on_b = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  std::array<std::int32_t, 4> feature_a{}, feature_b{};
};

// Record `m`, just built at the current poses (gap_bound: a lower bound of the gap when
// m is empty; normal_on_b: m's normal is a face normal of B).
KeptManifold keep_manifold(int ia, int ib, const PolyhedronView& a, const PolyhedronView& b,
                           const ContactManifold& m, double gap_bound, bool normal_on_b);

// The kept manifold at the current poses: every point's position and gap anew.
void replay_manifold(const KeptManifold& k, const PolyhedronView& a, const PolyhedronView& b, ContactManifold& out);

}  // namespace ratchet
