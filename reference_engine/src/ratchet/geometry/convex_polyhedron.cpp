#include "ratchet/geometry/convex_polyhedron.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <tuple>
#include <utility>

#include <Eigen/Eigenvalues>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace ratchet {
namespace {

// Relative size below which the point cloud counts as flat: a thinner solid has no
// usable inertia and Qhull's own roundoff handling becomes unreliable.
constexpr double kFlatTolerance = 1e-9;

[[noreturn]] void fail(const std::string& what, const std::string& why) {
  throw std::invalid_argument(what + ": " + why);
}

void validate(const std::vector<Vec3>& points, const std::string& what) {
  const std::string why = point_cloud_defect(points);
  if (!why.empty()) fail(what, why);
}

struct Hull {
  std::vector<int> input_index;        // hull vertex -> input point, ascending
  std::vector<std::vector<int>> faces;  // hull vertex indices, CCW seen from outside
};

// Runs Qhull (reentrant API) and reads the hull back; returns Qhull's exit code.
// Default options merge coplanar facets (pre-merge 'C-0'), so each Qhull facet is
// one polygon face.
int run_qhull(const std::vector<Vec3>& points, FILE* err, Hull& hull) {
  std::vector<coordT> coords(3 * points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k) coords[3 * i + static_cast<std::size_t>(k)] = points[i][k];

  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, err);
  char options[] = "qhull";
  const int code = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coords.data(), False,
                                options, nullptr, err);
  if (code == qh_ERRnone) {
    // Hull vertices (those of some facet) numbered in input order, so the result
    // does not depend on Qhull's ids.
    facetT* facet;
    vertexT *vertex, **vertexp;
    std::vector<int> renumber(points.size(), -1);
    FORALLfacets {
      FOREACHvertex_(facet->vertices) renumber[static_cast<std::size_t>(qh_pointid(qh, vertex->point))] = 0;
    }
    for (std::size_t i = 0; i < points.size(); ++i)
      if (renumber[i] == 0) {
        renumber[i] = static_cast<int>(hull.input_index.size());
        hull.input_index.push_back(static_cast<int>(i));
      }

    std::vector<std::pair<double, int>> by_angle;
    FORALLfacets {
      const Vec3 n(facet->normal[0], facet->normal[1], facet->normal[2]);  // outward
      Vec3 center = Vec3::Zero();
      by_angle.clear();
      FOREACHvertex_(facet->vertices) {
        const auto input = static_cast<std::size_t>(qh_pointid(qh, vertex->point));
        by_angle.emplace_back(0.0, renumber[input]);
        center += points[input];
      }
      center /= static_cast<double>(by_angle.size());
      // A convex polygon's vertices sorted by angle about its centre, with the
      // basis (e1, n x e1, n) right-handed, run counter-clockwise seen from outside.
      auto at = [&](int v) -> const Vec3& {
        return points[static_cast<std::size_t>(hull.input_index[static_cast<std::size_t>(v)])];
      };
      const Vec3 r0 = at(by_angle[0].second) - center;
      const Vec3 e1 = (r0 - n.dot(r0) * n).normalized();
      const Vec3 e2 = n.cross(e1);
      for (auto& [angle, v] : by_angle) {
        const Vec3 r = at(v) - center;
        angle = std::atan2(r.dot(e2), r.dot(e1));
      }
      std::sort(by_angle.begin(), by_angle.end());
      std::vector<int> face;
      face.reserve(by_angle.size());
      for (const auto& av : by_angle) face.push_back(av.second);
      // Canonical start (smallest index) so the face list can be sorted deterministically.
      std::rotate(face.begin(), std::min_element(face.begin(), face.end()), face.end());
      hull.faces.push_back(std::move(face));
    }
    std::sort(hull.faces.begin(), hull.faces.end());
  }

  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  if (curlong != 0 || totlong != 0)
    throw std::runtime_error("Qhull did not free " + std::to_string(totlong) + " bytes");
  return code;
}

Hull qhull_hull(const std::vector<Vec3>& points, const std::string& what) {
  // Qhull must stay silent: it writes to /dev/null, and only a failed run is
  // repeated into a memory stream to put Qhull's diagnostics in the exception.
  static FILE* const null_stream = std::fopen("/dev/null", "w");
  Hull hull;
  int code = qh_ERRother;
  if (null_stream != nullptr) {
    code = run_qhull(points, null_stream, hull);
    if (code == qh_ERRnone) return hull;
  }
  char* text = nullptr;
  std::size_t size = 0;
  FILE* err = open_memstream(&text, &size);
  if (err == nullptr) throw std::runtime_error(what + ": cannot open a stream for Qhull's messages");
  hull = Hull();
  code = run_qhull(points, err, hull);
  std::fclose(err);
  const std::string message = text ? text : "";
  std::free(text);
  if (code == qh_ERRnone) return hull;
  const std::string why = "Qhull failed (code " + std::to_string(code) + "): " + message;
  if (code == qh_ERRsingular || code == qh_ERRprec || code == qh_ERRinput) fail(what, why);
  throw std::runtime_error(what + ": " + why);
}

// Volume, centroid and inertia (per unit density, about the centroid) of the solid
// bounded by `faces`, summed over the signed tetrahedra (ref, a, b, c) of a fan
// triangulation of each face.
struct MassProperties {
  double volume = 0.0;
  Vec3 centroid = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();
};

MassProperties mass_properties(const std::vector<Vec3>& v, const std::vector<std::vector<int>>& faces) {
  auto for_each_tet = [&](auto&& f) {
    for (const auto& face : faces)
      for (std::size_t i = 1; i + 1 < face.size(); ++i)
        f(v[static_cast<std::size_t>(face[0])], v[static_cast<std::size_t>(face[i])],
          v[static_cast<std::size_t>(face[i + 1])]);
  };
  // Pass 1: centroid, from an interior reference point (vertex mean) to limit cancellation.
  Vec3 ref = Vec3::Zero();
  for (const Vec3& p : v) ref += p;
  ref /= static_cast<double>(v.size());
  double vol = 0.0;
  Vec3 moment = Vec3::Zero();
  for_each_tet([&](const Vec3& a, const Vec3& b, const Vec3& c) {
    const double tv = (a - ref).dot((b - ref).cross(c - ref)) / 6.0;
    vol += tv;
    moment += tv * (a + b + c - 3.0 * ref) / 4.0;
  });
  MassProperties mp;
  mp.centroid = ref + moment / vol;

  // Pass 2: signed tetrahedra from the centroid. Second moments C = int x x^T dV of
  // a tetrahedron with vertices 0, a, b, c: C = V/20 (a a^T + b b^T + c c^T + s s^T),
  // s = a + b + c, and I = tr(C) Id - C. This is the matrix form of the explicit
  // moments a, b, c and products a', b', c' of Tonon 2004, "Explicit exact formulas
  // for the 3-D tetrahedron inertia tensor in terms of its vertex coordinates",
  // J. Math. Stat. 1(1), with one vertex at the origin.
  Mat3 second = Mat3::Zero();
  vol = 0.0;
  for_each_tet([&](const Vec3& pa, const Vec3& pb, const Vec3& pc) {
    const Vec3 a = pa - mp.centroid, b = pb - mp.centroid, c = pc - mp.centroid, s = a + b + c;
    const double tv = a.dot(b.cross(c)) / 6.0;
    vol += tv;
    second += (tv / 20.0) * (a * a.transpose() + b * b.transpose() + c * c.transpose() +
                             s * s.transpose());
  });
  mp.volume = vol;
  mp.inertia = second.trace() * Mat3::Identity() - second;
  return mp;
}

// Principal axes as a proper rotation with a fixed sign convention: the largest
// component of the first two axes is positive, the third is their cross product.
Mat3 principal_axes(const Mat3& inertia, Vec3& moments) {
  const Eigen::SelfAdjointEigenSolver<Mat3> solver(0.5 * (inertia + inertia.transpose()));
  if (solver.info() != Eigen::Success) throw std::runtime_error("inertia diagonalisation failed");
  moments = solver.eigenvalues();  // ascending
  Mat3 r = solver.eigenvectors();
  for (int k = 0; k < 2; ++k) {
    Eigen::Index i = 0;
    r.col(k).cwiseAbs().maxCoeff(&i);
    if (r(i, k) < 0.0) r.col(k) = -r.col(k);
  }
  r.col(2) = r.col(0).cross(r.col(1)).normalized();
  return r;
}

// Normals, offsets, edges and bounding radius from vertices and faces.
void finish_shape(ConvexPolyhedron& s, const std::string& what) {
  s.face_normals.clear();
  s.face_offsets.clear();
  for (const auto& face : s.faces) {
    // Newell's normal: robust for polygons with (nearly) collinear vertices.
    Vec3 n = Vec3::Zero();
    for (std::size_t i = 0; i < face.size(); ++i) {
      const Vec3& a = s.vertices[static_cast<std::size_t>(face[i])];
      const Vec3& b = s.vertices[static_cast<std::size_t>(face[(i + 1) % face.size()])];
      n += a.cross(b);
    }
    n.normalize();
    // Max rather than mean: a merged face may be planar only to roundoff, and the
    // half-space must still hold all its vertices.
    double d = -INFINITY;
    for (int v : face) d = std::max(d, n.dot(s.vertices[static_cast<std::size_t>(v)]));
    s.face_normals.push_back(n);
    s.face_offsets.push_back(d);
  }

  // On a closed, consistently oriented surface every edge runs once each way;
  // edge_faces[e][0] is the face in which it runs edges[e][0] -> edges[e][1].
  struct HalfEdge {
    std::array<int, 2> edge;
    int reversed, face;
    bool operator<(const HalfEdge& o) const {
      return std::tie(edge, reversed, face) < std::tie(o.edge, o.reversed, o.face);
    }
  };
  std::vector<HalfEdge> half;
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const auto& face = s.faces[f];
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i], b = face[(i + 1) % face.size()];
      half.push_back({{std::min(a, b), std::max(a, b)}, a > b ? 1 : 0, static_cast<int>(f)});
    }
  }
  std::sort(half.begin(), half.end());
  s.edges.clear();
  s.edge_faces.clear();
  for (std::size_t i = 0; i < half.size(); i += 2) {
    if (i + 1 >= half.size() || half[i].edge != half[i + 1].edge || half[i].reversed != 0 ||
        half[i + 1].reversed != 1 || (i + 2 < half.size() && half[i + 2].edge == half[i].edge))
      throw std::runtime_error(what + ": hull surface is not a closed 2-manifold");
    s.edges.push_back(half[i].edge);
    s.edge_faces.push_back({half[i].face, half[i + 1].face});
  }

  // Counting sort of (vertex, face) incidences by vertex; faces ascending within each.
  s.vertex_face_start.assign(s.vertices.size() + 1, 0);
  for (const std::vector<int>& face : s.faces)
    for (int v : face) ++s.vertex_face_start[static_cast<std::size_t>(v) + 1];
  for (std::size_t v = 0; v < s.vertices.size(); ++v) s.vertex_face_start[v + 1] += s.vertex_face_start[v];
  s.vertex_face_list.assign(static_cast<std::size_t>(s.vertex_face_start.back()), 0);
  std::vector<int> fill(s.vertex_face_start.begin(), s.vertex_face_start.end() - 1);
  for (std::size_t f = 0; f < s.faces.size(); ++f)
    for (int v : s.faces[f]) s.vertex_face_list[static_cast<std::size_t>(fill[static_cast<std::size_t>(v)]++)] = static_cast<int>(f);

  // Face sides: (edge direction) x (outward normal) points out of a counter-clockwise
  // face; the offset is the larger over the side's two ends (a merged face is planar
  // only to roundoff, as for the face offsets above).
  s.face_side_start.assign(1, 0);
  s.face_side_normals.clear();
  s.face_side_offsets.clear();
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const auto& face = s.faces[f];
    for (std::size_t i = 0; i < face.size(); ++i) {
      const Vec3& a = s.vertices[static_cast<std::size_t>(face[i])];
      const Vec3& b = s.vertices[static_cast<std::size_t>(face[(i + 1) % face.size()])];
      const Vec3 out = (b - a).cross(s.face_normals[f]).normalized();
      s.face_side_normals.push_back(out);
      s.face_side_offsets.push_back(std::max(out.dot(a), out.dot(b)));
    }
    s.face_side_start.push_back(static_cast<int>(s.face_side_normals.size()));
  }
  s.edge_directions.clear();
  for (const auto& e : s.edges)
    s.edge_directions.push_back((s.vertices[static_cast<std::size_t>(e[1])] - s.vertices[static_cast<std::size_t>(e[0])]).normalized());

  s.bounding_radius = 0.0;
  for (const Vec3& v : s.vertices) s.bounding_radius = std::max(s.bounding_radius, v.norm());
  s.min_face_offset = *std::min_element(s.face_offsets.begin(), s.face_offsets.end());
}

}  // namespace

std::string point_cloud_defect(const std::vector<Vec3>& points) {
  if (points.size() < 4) return "need at least 4 points for a solid hull, got " + std::to_string(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!points[i].allFinite()) return "point " + std::to_string(i) + " is not finite";
  const Vec3& p0 = points[0];
  double d1 = 0.0;
  Vec3 p1 = p0;
  for (const Vec3& p : points)
    if ((p - p0).norm() > d1) d1 = (p - p0).norm(), p1 = p;
  if (!(d1 > 0.0)) return "all points coincide; expected a 3-D point cloud";
  const Vec3 axis = (p1 - p0) / d1;
  double d2 = 0.0;
  Vec3 p2 = p0;
  for (const Vec3& p : points) {
    const double d = (p - p0).cross(axis).norm();
    if (d > d2) d2 = d, p2 = p;
  }
  if (d2 <= kFlatTolerance * d1) return "points are collinear; expected a 3-D point cloud";
  const Vec3 normal = (p1 - p0).cross(p2 - p0).normalized();
  double d3 = 0.0;
  for (const Vec3& p : points) d3 = std::max(d3, std::abs((p - p0).dot(normal)));
  if (d3 <= kFlatTolerance * d1) return "points are coplanar; expected a 3-D point cloud";
  return "";
}

PolyhedronBuild build_convex_polyhedron(const std::vector<Vec3>& points, const std::string& what) {
  validate(points, what);
  Hull hull = qhull_hull(points, what);

  std::vector<Vec3> input_frame;
  for (int i : hull.input_index) input_frame.push_back(points[static_cast<std::size_t>(i)]);
  const MassProperties mp = mass_properties(input_frame, hull.faces);
  if (!(mp.volume > 0.0)) fail(what, "hull has no volume; expected a 3-D point cloud");

  PolyhedronBuild out;
  out.centroid = mp.centroid;
  out.rotation = principal_axes(mp.inertia, out.shape.principal_inertia);
  out.shape.volume = mp.volume;
  out.shape.faces = std::move(hull.faces);
  for (const Vec3& p : input_frame) out.shape.vertices.push_back(out.rotation.transpose() * (p - out.centroid));
  finish_shape(out.shape, what);
  return out;
}

PolyhedronBuild build_box(const Vec3& h, const std::string& what) {
  if (!h.allFinite() || !(h.minCoeff() > 0.0)) fail(what, "half extents must be positive and finite");
  // Below this the hull's flatness test (thickness 2 min h against extent <= 2 |h|) would
  // call the box collinear or coplanar; say why instead.
  if (!(h.minCoeff() > kFlatTolerance * h.norm()))
    fail(what, "the smallest half extent is not above 1e-9 of the half diagonal; expected a solid box");
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i)
    corners.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
  // Qhull gives the topology; the box keeps its own axes (they are principal) and
  // exact corners, so build_box(h).shape spans [-h, h] whatever the moment order.
  PolyhedronBuild out = build_convex_polyhedron(corners, what);
  out.centroid = Vec3::Zero();
  out.rotation = Mat3::Identity();
  out.shape.vertices = corners;  // all 8 corners are hull vertices, kept in input order
  const double v = 8.0 * h.prod();
  out.shape.volume = v;
  const Vec3 h2 = h.cwiseProduct(h);
  out.shape.principal_inertia = v / 3.0 * Vec3(h2.y() + h2.z(), h2.x() + h2.z(), h2.x() + h2.y());
  finish_shape(out.shape, what);
  return out;
}

}  // namespace ratchet
