// A polyhedron placed in the world for one step: the body's shape, its centre of mass,
// rotation and thermal scale, and its vertices already transformed (per-step scratch).
#pragma once

#include <vector>

#include "ratchet/geometry/convex_polyhedron.hpp"

namespace ratchet {

struct PolyhedronView {
  const ConvexPolyhedron* shape = nullptr;
  const Vec3* world_vertices = nullptr;  // shape->vertices.size() points: center + scale * R * v
  Vec3 center = Vec3::Zero();
  Mat3 R = Mat3::Identity();             // body -> world
  double scale = 1.0;                    // thermal scale s_p

  Vec3 face_normal(int f) const { return R * shape->face_normals[static_cast<std::size_t>(f)]; }
  // Plane offset d of face f in the world: {x : face_normal(f) . x = d}.
  double face_offset(int f) const {
    return face_normal(f).dot(center) + scale * shape->face_offsets[static_cast<std::size_t>(f)];
  }
};

}  // namespace ratchet
