// The mutable state of a run: everything that carries from one step to the next
// (poses, velocities, scales, the impulses and common planes kept for warm starting,
// the manifolds kept for reuse).
// State plus the SceneDef is all a restart needs (`ratchet run --packing` starts from a saved State).
#pragma once

#include <cstdint>
#include <tuple>
#include <vector>

#include "ratchet/contact/common_plane.hpp"
#include "ratchet/contact/manifold_reuse.hpp"
#include "ratchet/core/types.hpp"

namespace ratchet {

// A contact point's identity across steps. b < 0 denotes wall -1 - b.
struct ContactKey {
  int a = 0, b = 0;
  std::int32_t feature_a = 0, feature_b = 0;
  bool operator<(const ContactKey& o) const {
    return std::tie(a, b, feature_a, feature_b) < std::tie(o.a, o.b, o.feature_a, o.feature_b);
  }
  bool operator==(const ContactKey& o) const {
    return a == o.a && b == o.b && feature_a == o.feature_a && feature_b == o.feature_b;
  }
};

struct KeptImpulse {
  ContactKey key;
  Vec3 impulse = Vec3::Zero();  // world frame, on A
};

// The common plane of a polyhedron pair, kept to warm-start the next step's search
// (docs/method.md s. 3).
struct KeptPlane {
  int a = 0, b = 0;
  CommonPlaneCache cache;
};

struct State {
  std::int64_t step = 0;
  double t = 0.0;
  double T = 0.0;    // temperature at t
  double s_p = 1.0;  // particle scale at t
  double s_c = 1.0;  // container scale at t
  std::vector<Vec3> x, v, w;  // centre of mass, velocity, angular velocity (world)
  std::vector<Quat> q;        // orientation, body -> world
  std::vector<KeptImpulse> impulses;  // sorted by key
  // Sorted by (a, b). Between steps one entry per candidate pair of the broad phase
  // (world/detect.cpp keeps them in place); an entry with cache.valid false, or
  // count -1, holds nothing. State files keep only the others (io/state_file.hpp), and
  // a state read from one has only those.
  std::vector<KeptPlane> planes;
  std::vector<KeptManifold> manifolds;  // only with solver.manifold_reuse > 0
};

}  // namespace ratchet
