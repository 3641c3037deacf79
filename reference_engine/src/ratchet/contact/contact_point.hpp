// What the narrow phase hands to the solver. Conventions (docs/method.md):
// body A is the first body of a pair, B the second body or a wall; the normal n is a
// unit vector pointing from B towards A (the direction in which A is pushed);
// the gap g is the signed distance along n, negative for overlap.
#pragma once

#include <array>
#include <cstdint>

#include "ratchet/core/types.hpp"

namespace ratchet {

// Feature ids identify a contact point across steps for warm starting.
enum class FeatureKind : std::int32_t { Vertex = 0, Edge = 1, Face = 2 };
constexpr std::int32_t feature_id(FeatureKind kind, int index) {
  return (static_cast<std::int32_t>(kind) << 24) | static_cast<std::int32_t>(index);
}

struct ContactPoint {
  Vec3 point = Vec3::Zero();   // world frame, on (or midway across) the common plane
  Vec3 normal = Vec3::UnitZ(); // unit, from B towards A
  double gap = 0.0;            // signed distance along normal
  std::int32_t feature_a = 0;
  std::int32_t feature_b = 0;
};

// At most 4 points per body pair: enough for a face on a face to resist rocking.
struct ContactManifold {
  std::array<ContactPoint, 4> points;
  int count = 0;
  void add(const ContactPoint& c) { points[static_cast<std::size_t>(count++)] = c; }
};

}  // namespace ratchet
