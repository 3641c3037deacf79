// A rigid convex polyhedron in its body frame: centroid at the origin, axes along
// the principal axes of inertia. Built from any point cloud by Qhull.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "ratchet/core/types.hpp"

namespace ratchet {

struct ConvexPolyhedron {
  std::vector<Vec3> vertices;             // body frame, hull vertices only, in input order
  std::vector<std::vector<int>> faces;    // vertex indices, counter-clockwise seen from outside;
                                          // coplanar hull facets merged into one polygon
  std::vector<Vec3> face_normals;         // outward unit normals
  std::vector<double> face_offsets;       // face f is {x : face_normals[f] . x = face_offsets[f]}
  std::vector<std::array<int, 2>> edges;  // unique, edges[e][0] < edges[e][1], sorted
  std::vector<std::array<int, 2>> edge_faces;  // the two faces that share edge e; in face
                                               // edge_faces[e][0] it runs edges[e][0] -> [1]
  // Faces around vertex v, ascending: vertex_face_list[vertex_face_start[v] ..
  // vertex_face_start[v + 1]). Flat (CSR) rather than a vector per vertex: the manifold
  // reads it for every contact pair, and one indirection less saves cache misses.
  std::vector<int> vertex_face_start;
  std::vector<int> vertex_face_list;
  // Read by the common-plane certificate (contact/common_plane_certificate.cpp), which proves that a
  // contact facet stays the best one without a new search:
  //  * the sides of face f, one per vertex of faces[f] (side i runs from faces[f][i] to
  //    faces[f][i + 1]): in-plane outward unit normal and offset, so that a point x of
  //    the face's plane lies inside the face iff face_side_offsets[k] - face_side_normals[k] . x
  //    >= 0 for k = face_side_start[f] .. face_side_start[f + 1] - 1;
  //  * edge_directions[e]: unit vector from edges[e][0] to edges[e][1].
  std::vector<int> face_side_start;
  std::vector<Vec3> face_side_normals;
  std::vector<double> face_side_offsets;
  std::vector<Vec3> edge_directions;
  double volume = 0.0;                    // at scale 1
  Vec3 principal_inertia = Vec3::Zero();  // per unit density at scale 1: I = diag(principal_inertia);
                                          // ascending, except build_box (x, y, z order)
  double bounding_radius = 0.0;           // max |vertex| (about the centroid)
  double min_face_offset = 0.0;           // min face offset: the inradius about the centroid
                                          // (the largest ball there inside), if positive
};

// A hull and the frame it was built in: input point p maps to body frame as
// rotation.transpose() * (p - centroid).
struct PolyhedronBuild {
  ConvexPolyhedron shape;
  Vec3 centroid = Vec3::Zero();  // centroid of the solid in the input frame
  Mat3 rotation = Mat3::Identity();  // columns: principal axes in the input frame (det +1)
};

// Builds the convex hull of `points` with Qhull and its exact mass properties
// (volume, centroid, inertia by signed tetrahedra, Tonon 2004, J. Math. Stat. 1(1)).
// Throws std::invalid_argument naming `what` if the points are fewer than 4,
// non-finite or (nearly) coplanar (thickness <= 1e-9 of the cloud's extent).
// Faces start at their smallest vertex index and are sorted; the rotation's first two
// columns have their largest component positive, the third is their cross product.
PolyhedronBuild build_convex_polyhedron(const std::vector<Vec3>& points,
                                        const std::string& what = "polyhedron");

// Why `points` cannot span a solid, or "" if they can: fewer than 4 points, a
// non-finite point, or all points coincident, collinear or coplanar within 1e-9 of the
// cloud's size (greedy extreme-point simplex). Every Qhull caller checks this first.
std::string point_cloud_defect(const std::vector<Vec3>& points);

// Closed-form helper: the axis-aligned box with the given half extents. Keeps the
// input axes (rotation = identity, vertices exactly +-h), so principal_inertia is in
// x, y, z order rather than ascending. Throws std::invalid_argument naming `what` unless
// h > 0, finite, and its smallest component is more than 1e-9 of |h|.
PolyhedronBuild build_box(const Vec3& half_extents, const std::string& what = "box");

}  // namespace ratchet
