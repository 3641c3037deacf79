// The plane certificate (docs/method.md section 3): a proof that the cached facet F of
// D is still the best one, so that the SAT (sat_search) can be skipped with the result
// it would give, bit for bit. In a resting bed most overlapping pairs keep their facet
// for many steps, and the SAT bounds every face and edge of both bodies to show it
// again (docs/performance.md).
//
// h(nu) = max_{d in D} nu.d is the support function of D = A - B; a facet G with outward
// normal nu_G has s_G = -h(nu_G), and the SAT returns the facet of largest s, F, with
// delta = h(nu_F) >= 0 the overlap. theta is the angle between nu and nu_F. Three
// regions of directions, which together cover the sphere:
//  * Nearest, theta < kCertEnum: these facets are enumerated (the faces of both bodies
//    whose normals lie there, the edge pairs of the edges nearly orthogonal to nu_F;
//    listed when the certificate is made, with room for the pair to turn by kCertTurn)
//    and their values computed exactly as the SAT computes them: none may exceed s_F.
//    A resting contact lies flat (an edge or face on a face), so its competitors are
//    here, a rounding-sized distance below F.
//  * Near, kCertEnum <= theta <= theta0: if the origin's projection onto F's plane lies
//    in F with a disk of radius m around it, D contains that disk, so
//    h(nu) >= delta cos(theta) + m sin(theta), i.e. for 0 < theta < pi / 2
//    h(nu) - delta >= sin(theta) (m - delta tan(theta / 2))
//                  >= sin(kCertEnum) (m - delta tan(theta0 / 2)).
//  * Far, theta > kCertFarAngle from the facet normal of the step that made the
//    certificate: while the origin is inside D, h has no local minimum on the sphere
//    but at facet normals (it is linear on each vertex cell and positive), so its
//    minimum over the region is attained at a facet normal in it or on its boundary
//    circle, where the disk bound holds. That step bounds s over the region by a scan
//    with the SAT's bounds (far_bound). Later, every point of D has moved by at most mu
//    in A's frame, so h of a fixed direction of A's frame by at most mu: the region's
//    facets have s <= far_bound + mu.
// theta0 is kCertFarAngle plus the angle nu_F has turned in A's frame since (at most
// kCertTurn). The near and far bounds must leave every facet there kCertMargin L below F.
#include <algorithm>
#include <array>
#include <cmath>

#include "ratchet/contact/common_plane_detail.hpp"

namespace ratchet::cp_detail {

namespace {

// Radius of the largest disk about world point x (on face f's plane) inside face f.
double face_disk(const PolyhedronView& p, int f, const Vec3& x) {
  const ConvexPolyhedron& P = *p.shape;
  const Vec3 xb = p.R.transpose() * (x - p.center) / p.scale;
  double lo = kInf;
  for (int k = P.face_side_start[static_cast<std::size_t>(f)]; k < P.face_side_start[static_cast<std::size_t>(f) + 1]; ++k)
    lo = std::min(lo, P.face_side_offsets[static_cast<std::size_t>(k)] - P.face_side_normals[static_cast<std::size_t>(k)].dot(xb));
  return p.scale * lo;
}

bool certifiable(const PolyhedronView& p) {
  return p.shape->face_side_start.size() == p.shape->faces.size() + 1 &&
         p.shape->edge_directions.size() == p.shape->edges.size();
}

// Radius of the disk about the origin's projection that facet F (CP normal F.n, value
// s, supports av along F.n) holds: F = face of A - vertex of B, vertex of A - face of B,
// or edge of A - edge of B (a parallelogram). <= 0: the projection is not inside F.
double facet_disk(const PolyhedronView& a, const PolyhedronView& b, const Candidate& F, double s,
                  const AxisValue& av) {
  const double delta = -s;
  switch (F.kind) {
    case PlaneFeature::FaceA:  // n = -m: the point of face f above B's vertex
      return face_disk(a, F.index_a, b.world_vertices[av.ib] - delta * F.n);
    case PlaneFeature::FaceB:  // n = m
      return face_disk(b, F.index_b, a.world_vertices[av.ia] + delta * F.n);
    case PlaneFeature::EdgeEdge: {
      const auto& ea = a.shape->edges[static_cast<std::size_t>(F.index_a)];
      const auto& eb = b.shape->edges[static_cast<std::size_t>(F.index_b)];
      const Vec3 &a0 = a.world_vertices[ea[0]], &b0 = b.world_vertices[eb[0]];
      const Vec3 u = a.world_vertices[ea[1]] - a0, w = b.world_vertices[eb[1]] - b0, r = a0 - b0;
      // Closest points a0 + sigma u and b0 + tau w of the two lines: the projection.
      const double uu = u.dot(u), uw = u.dot(w), ww = w.dot(w), ur = u.dot(r), wr = w.dot(r);
      const double den = uu * ww - uw * uw;
      if (!(den > 0.0)) return 0.0;
      const double sigma = (uw * wr - ww * ur) / den, tau = (uu * wr - uw * ur) / den;
      const double lu = std::sqrt(uu), lw = std::sqrt(ww);
      // A point sigma u + tau w of the parallelogram lies sigma |u| sin(phi) from its
      // side along w, and so on.
      return std::sqrt(den) / (lu * lw) * std::min({sigma * lu, (1.0 - sigma) * lu, tau * lw, (1.0 - tau) * lw});
    }
    default:
      return 0.0;
  }
}

// Lists in `cert` the features that can span a facet within kCertEnum of nu = -F.n
// while nu and B's orientation in A's frame turn by less than kCertTurn (see
// certificate_holds): faces within kCertEnum + kCertTurn of nu; edges e with
// |nu.e| <= 2 sin(kCertEnum / 2) + kCertTurn (a facet normal within theta of nu is
// orthogonal to both its edges, so each has |nu.e| <= |nu - n| = 2 sin(theta / 2)).
// Slightly wider than that, so rounding cannot leave one out. False if they do not fit.
bool list_nearest(const PolyhedronView& a, const PolyhedronView& b, const Candidate& F, PlaneCertificate& cert) {
  const Vec3 nu_a = a.R.transpose() * -F.n, nu_b = b.R.transpose() * -F.n;
  const double cos_face = std::cos(1.01 * (kCertEnum + kCertTurn));
  const double edge_cos = 1.01 * (2.0 * std::sin(0.5 * kCertEnum) + kCertTurn);
  int fa = 0, fb = 0, ea = 0, eb = 0;
  const ConvexPolyhedron &A = *a.shape, &B = *b.shape;
  if (A.faces.size() > 32767 || B.faces.size() > 32767 || A.edges.size() > 32767 || B.edges.size() > 32767) return false;
  for (std::size_t f = 0; f < A.faces.size(); ++f) {
    if ((F.kind == PlaneFeature::FaceA && F.index_a == static_cast<int>(f)) || A.face_normals[f].dot(nu_a) < cos_face) continue;
    if (fa == PlaneCertificate::kFaces) return false;
    cert.face_a[static_cast<std::size_t>(fa++)] = static_cast<std::int16_t>(f);
  }
  for (std::size_t g = 0; g < B.faces.size(); ++g) {
    if ((F.kind == PlaneFeature::FaceB && F.index_b == static_cast<int>(g)) || -B.face_normals[g].dot(nu_b) < cos_face) continue;
    if (fb == PlaneCertificate::kFaces) return false;
    cert.face_b[static_cast<std::size_t>(fb++)] = static_cast<std::int16_t>(g);
  }
  for (std::size_t e = 0; e < A.edges.size(); ++e) {
    if (!(std::abs(A.edge_directions[e].dot(nu_a)) <= edge_cos)) continue;
    if (ea == PlaneCertificate::kEdges) return false;
    cert.edge_a[static_cast<std::size_t>(ea++)] = static_cast<std::int16_t>(e);
  }
  for (std::size_t e = 0; e < B.edges.size(); ++e) {
    if (!(std::abs(B.edge_directions[e].dot(nu_b)) <= edge_cos)) continue;
    if (eb == PlaneCertificate::kEdges) return false;
    cert.edge_b[static_cast<std::size_t>(eb++)] = static_cast<std::int16_t>(e);
  }
  cert.faces_a = static_cast<std::int8_t>(fa);
  cert.faces_b = static_cast<std::int8_t>(fb);
  cert.edges_a = static_cast<std::int8_t>(ea);
  cert.edges_b = static_cast<std::int8_t>(eb);
  return true;
}

// The nearest region: the listed features' facets, evaluated as the SAT evaluates them.
// False if one could replace F (value s) in the SAT: a value above s (offer() keeps a
// facet on a tie), or (F an edge pair) a face within the SAT's tie rescan of s, whose
// outcome depends on which faces the SAT's pruning let through.
bool nearest_below(const PolyhedronView& a, const PolyhedronView& b, const Candidate& F, double s,
                   const PlaneCertificate& cert) {
  const bool edge_start = F.kind == PlaneFeature::EdgeEdge;
  const double face_limit = edge_start ? s - kTieRescan * pair_length(a, b) : s;
  auto face_replaces = [&](double v) { return edge_start ? v >= face_limit : v > s; };
  Vec3 n;
  for (int k = 0; k < cert.faces_a; ++k)
    if (face_replaces(face_a_value(a, b, cert.face_a[static_cast<std::size_t>(k)], n))) return false;
  for (int k = 0; k < cert.faces_b; ++k)
    if (face_replaces(face_b_value(a, b, cert.face_b[static_cast<std::size_t>(k)], n))) return false;
  std::array<EdgeData, PlaneCertificate::kEdges> eb;
  for (int k = 0; k < cert.edges_b; ++k) eb[static_cast<std::size_t>(k)] = edge_data(b, cert.edge_b[static_cast<std::size_t>(k)]);
  for (int i = 0; i < cert.edges_a; ++i) {
    const EdgeData x = edge_data(a, cert.edge_a[static_cast<std::size_t>(i)]);
    for (int k = 0; k < cert.edges_b; ++k) {
      const EdgeData& y = eb[static_cast<std::size_t>(k)];
      if (F.kind == PlaneFeature::EdgeEdge && x.e == F.index_a && y.e == F.index_b) continue;
      double v = 0.0;
      if (edge_pair_facet(x, y, v, n) && v > s) return false;
    }
  }
  return true;
}

// Upper bound of s over the facets of D at least kCertFarAngle from nu = -F.n: the
// SAT's bounds (sat_search) against lim = F.s - kCertSlack L, the facets that pass
// them evaluated, the nearer ones left to the other two regions.
double far_scan(const PolyhedronView& a, const PolyhedronView& b, const Candidate& F) {
  thread_local SatScratch sc;
  const Vec3 nu = -F.n;
  const Vec3 d = a.center - b.center;
  const double rho = inradius(a) + inradius(b);
  const double L = pair_length(a, b);
  const double lim = F.s - kCertSlack * L;
  const double cos_far = std::cos(kCertFarAngle);
  std::array<int, kRefVertices> ref_a{}, ref_b{};
  const int na = top_supports(a, nu, ref_a);
  const int nb = top_supports(b, F.n, ref_b);
  face_bounds(a, -1.0, d, b, ref_b, nb, rho, lim, sc.a);
  face_bounds(b, +1.0, d, a, ref_a, na, rho, lim, sc.b);
  double top = lim + kPruneSafety * L;  // what every pruned facet is proven below
  Vec3 n;
  for (const int f : sc.a.candidates)
    if (face_may_win(sc.a, f, rho, lim) && a.face_normal(f).dot(nu) < cos_far) top = std::max(top, face_a_value(a, b, f, n));
  for (const int g : sc.b.candidates)
    if (face_may_win(sc.b, g, rho, lim) && -b.face_normal(g).dot(nu) < cos_far) top = std::max(top, face_b_value(a, b, g, n));
  active_edges(a, sc.a, rho, lim, sc.ea);
  if (sc.ea.empty()) return top;
  active_edges(b, sc.b, rho, lim, sc.eb);
  for (const EdgeData& ea : sc.ea)
    for (const EdgeData& eb : sc.eb) {
      double v = 0.0;
      if (edge_pair_facet(ea, eb, v, n) && -n.dot(nu) < cos_far) top = std::max(top, v);
    }
  return top;
}

// Lower bound of h - delta over the near region for turn angle theta0 (see above).
double near_bound(double disk, double s, double theta0) {
  return std::sin(kCertEnum) * (disk + s * std::tan(0.5 * theta0));
}

}  // namespace

// Makes the certificate of facet F (the SAT's result, s its scanned value <= 0) when
// the pair is certifiable now: the next steps then check it instead of searching.
void make_certificate(const PolyhedronView& a, const PolyhedronView& b, const Candidate& F, double s,
                      PlaneCertificate& cert) {
  cert.valid = false;
  if (!(s <= 0.0) || !certifiable(a) || !certifiable(b)) return;
  const double margin = kCertMargin * pair_length(a, b);
  const AxisValue av = evaluate_axis(a, b, F.n);
  const double disk = facet_disk(a, b, F, s, av);
  if (!(near_bound(disk, s, kCertFarAngle + kCertTurn) > margin)) return;
  if (!list_nearest(a, b, F, cert) || !nearest_below(a, b, F, s, cert)) return;
  Candidate at = F;
  at.s = s;
  const double circle = -(-s * std::cos(kCertFarAngle) + disk * std::sin(kCertFarAngle));
  cert.far_bound = std::max(far_scan(a, b, at), circle);
  if (!(cert.far_bound + margin < s)) return;  // could never hold
  cert.rotation = a.R.transpose() * b.R;
  cert.offset = a.R.transpose() * (b.center - a.center);
  cert.scale_a = a.scale;
  cert.scale_b = b.scale;
  cert.normal_a = a.R.transpose() * (-F.n);
  cert.valid = true;
}

// Does the certificate prove that the start facet F (its scanned value F.s, supports
// av) is what the SAT would return at the current pose?
bool certificate_holds(const PolyhedronView& a, const PolyhedronView& b, const PlaneCertificate& cert,
                       const Candidate& F, const AxisValue& av) {
  if (!cert.valid || !(F.s <= 0.0)) return false;
  const double margin = kCertMargin * pair_length(a, b);
  const Mat3 Rt = a.R.transpose();
  const Mat3 rotation = Rt * b.R;
  const Vec3 offset = Rt * (b.center - a.center);
  // Largest displacement of a point of D in A's frame since the certificate was made.
  const double mu = std::abs(a.scale - cert.scale_a) * a.shape->bounding_radius + (offset - cert.offset).norm() +
                    (b.scale * rotation - cert.scale_b * cert.rotation).norm() * b.shape->bounding_radius;
  if (!(cert.far_bound + mu + margin < F.s)) return false;
  // Turn of nu_F and of B in A's frame (|R1 - R0|_F = 2 sqrt(2) sin(angle / 2); acos
  // and asin lose ~1e-8 rad near their ends: add 1e-7).
  const double turn = std::acos(std::clamp((Rt * (-F.n)).dot(cert.normal_a), -1.0, 1.0)) + 1e-7;
  const double spin = 2.0 * std::asin(std::min(1.0, (rotation - cert.rotation).norm() / (2.0 * std::sqrt(2.0)))) + 1e-7;
  if (!(turn + spin <= kCertTurn)) return false;
  if (!(near_bound(facet_disk(a, b, F, F.s, av), F.s, kCertFarAngle + turn) > margin)) return false;
  return nearest_below(a, b, F, F.s, cert);
}

}  // namespace ratchet::cp_detail
