// Common Plane narrow phase: exact plane by SAT (overlap) or GJK (separation), then the
// contact region by clipping. See common_plane.hpp for the method and its sources. This
// file holds the public entry points, the warm start from the cache and the order the
// algorithms run in; the algorithms are in common_plane_{gjk,search,certificate,region}.cpp
// and their shared tolerances and helpers in common_plane_detail.hpp.
#include "ratchet/contact/common_plane.hpp"

#include <cmath>

#include "ratchet/contact/common_plane_detail.hpp"

namespace ratchet {

namespace cp_detail {
namespace {

// Current axis of a cached facet, or false if the cache holds none.
bool cached_axis(const PolyhedronView& a, const PolyhedronView& b, const CommonPlaneCache& cache, Vec3& n) {
  switch (cache.kind) {
    case PlaneFeature::FaceA:
      if (cache.index_a < 0 || cache.index_a >= static_cast<int>(a.shape->faces.size())) return false;
      n = -a.face_normal(cache.index_a);
      return true;
    case PlaneFeature::FaceB:
      if (cache.index_b < 0 || cache.index_b >= static_cast<int>(b.shape->faces.size())) return false;
      n = b.face_normal(cache.index_b);
      return true;
    case PlaneFeature::EdgeEdge: {
      if (cache.index_a < 0 || cache.index_a >= static_cast<int>(a.shape->edges.size())) return false;
      if (cache.index_b < 0 || cache.index_b >= static_cast<int>(b.shape->edges.size())) return false;
      const auto& ea = a.shape->edges[static_cast<std::size_t>(cache.index_a)];
      const auto& eb = b.shape->edges[static_cast<std::size_t>(cache.index_b)];
      const Vec3 u = a.world_vertices[ea[1]] - a.world_vertices[ea[0]];
      const Vec3 w = b.world_vertices[eb[1]] - b.world_vertices[eb[0]];
      Vec3 c = u.cross(w);
      const double len2 = c.squaredNorm();
      if (!(len2 > kParallelEdgesSin2 * u.squaredNorm() * w.squaredNorm())) return false;
      c /= std::sqrt(len2);
      n = c.dot(cache.normal) < 0.0 ? Vec3(-c) : c;
      return true;
    }
    default:
      return false;
  }
}

void store(CommonPlaneCache& cache, const Candidate& c) {
  cache.certificate.valid = false;
  cache.valid = true;
  cache.normal = c.n;
  cache.kind = c.kind;
  cache.index_a = c.index_a;
  cache.index_b = c.index_b;
  cache.simplex_count = 0;
}

void store_simplex(CommonPlaneCache& cache, const Vec3& n, const Simplex& s) {
  cache.certificate.valid = false;
  cache.valid = true;
  cache.normal = n;
  cache.kind = PlaneFeature::Simplex;
  cache.index_a = cache.index_b = -1;
  cache.simplex_count = s.n;
  for (int k = 0; k < s.n; ++k)
    cache.simplex[static_cast<std::size_t>(k)] = {s.v[static_cast<std::size_t>(k)].ia, s.v[static_cast<std::size_t>(k)].ib};
}

Simplex single_vertex(const PolyhedronView& a, const PolyhedronView& b, int ia, int ib) {
  Simplex s;
  s.n = 1;
  s.v[0].ia = ia;
  s.v[0].ib = ib;
  s.v[0].w = a.world_vertices[ia] - b.world_vertices[ib];
  return s;
}

// The common plane; with a finite cutoff it may stop as soon as g > cutoff is proven.
CommonPlaneResult solve(const PolyhedronView& a, const PolyhedronView& b, CommonPlaneCache& cache,
                        double cutoff) {
  CommonPlaneResult r;
  Candidate best;
  Simplex seed;
  bool try_gjk = false;

  // The start axis's value, kept: when no facet beats the start (a warm-started resting
  // contact) finish() reports it without a second scan of the vertices.
  bool start_known = false;
  Vec3 start_n = Vec3::Zero();
  double start_s = 0.0;
  AxisValue start_av;
  auto finish = [&](const Candidate& c) {
    // The gap reported is s(n) over the world vertices at the normal reported.
    r.normal = c.n;
    r.gap = start_known && c.n == start_n ? start_s : evaluate_axis(a, b, c.n).s;
    r.feature = c.kind;
    r.separated = r.gap > 0.0;
    return r;
  };
  auto early = [&](const Candidate& c) {
    r.normal = c.n;
    r.gap = c.s;
    r.feature = c.kind;
    r.separated = true;
    r.early_out = true;
    return r;
  };

  // 1. Start: the cached simplex (apart last step), the cached facet re-evaluated at the
  //    new poses, the cached normal, or cold the line of centres.
  const int nva = vertex_count(a), nvb = vertex_count(b);
  bool simplex_ok = cache.valid && cache.kind == PlaneFeature::Simplex && cache.simplex_count > 0;
  for (int k = 0; simplex_ok && k < cache.simplex_count; ++k) {
    const auto& p = cache.simplex[static_cast<std::size_t>(k)];
    simplex_ok = p[0] >= 0 && p[0] < nva && p[1] >= 0 && p[1] < nvb;
  }
  if (simplex_ok) {
    seed.n = cache.simplex_count;
    for (int k = 0; k < seed.n; ++k) {
      const auto& p = cache.simplex[static_cast<std::size_t>(k)];
      seed.v[static_cast<std::size_t>(k)] = single_vertex(a, b, p[0], p[1]).v[0];
    }
    try_gjk = true;
    best.kind = PlaneFeature::Simplex;
  } else {
    Vec3 n0;
    PlaneFeature kind = PlaneFeature::Axis;
    if (cache.valid && cached_axis(a, b, cache, n0)) {
      kind = cache.kind;
    } else if (cache.valid && cache.normal.squaredNorm() > 0.0) {
      n0 = cache.normal.normalized();
    } else {
      const Vec3 d = a.center - b.center;
      n0 = d.squaredNorm() > 0.0 ? Vec3(d.normalized()) : Vec3::UnitZ();
    }
    const AxisValue av = evaluate_axis(a, b, n0);
    start_av = av;
    ++r.sat_axes;
    start_known = true;
    start_n = n0;
    start_s = av.s;
    best.s = av.s;
    best.n = n0;
    best.kind = kind;
    if (kind != PlaneFeature::Axis) {
      best.index_a = cache.index_a;
      best.index_b = cache.index_b;
    }
    if (best.s > cutoff) {
      store(cache, best);
      return early(best);
    }
    if (best.s > 0.0) {
      seed = single_vertex(a, b, av.ia, av.ib);
      try_gjk = true;
    }
  }

  // 2. Apart (or apart last step): GJK distance.
  bool gjk_done = false;
  GjkOutcome go;
  if (try_gjk) {
    go = gjk(a, b, seed, cutoff);
    r.gjk_iterations += go.iterations;
    gjk_done = true;
    offer(best, go.s, go.n, PlaneFeature::Simplex, -1, -1);
    if (go.early_out) {
      store_simplex(cache, go.n, go.simplex);
      return early(best);
    }
  }

  // 3. Not proven apart: SAT over the facets of D (exact when they overlap).
  if (!(gjk_done && go.proven_apart)) {
    if (simplex_ok) {
      // Apart last step, touching or overlapping now: GJK may have enclosed the origin
      // before producing a useful bound, so the SAT starts from the cached normal, which
      // is within the step's motion of the optimum.
      const Vec3 n0 = cache.normal.squaredNorm() > 0.0 ? Vec3(cache.normal.normalized()) : Vec3::UnitZ();
      ++r.sat_axes;
      offer(best, evaluate_axis(a, b, n0).s, n0, PlaneFeature::Axis, -1, -1);
    }
    const bool facet_start = !simplex_ok && start_known &&
                             (best.kind == PlaneFeature::FaceA || best.kind == PlaneFeature::FaceB ||
                              best.kind == PlaneFeature::EdgeEdge);
    if (facet_start && certificate_holds(a, b, cache.certificate, best, start_av)) {
      // Proven: the SAT would keep the start facet, and report it as below.
      const PlaneCertificate cert = cache.certificate;
      store(cache, best);
      cache.certificate = cert;
      r.certified = true;
      return finish(best);
    }
    const Candidate start = best;
    Candidate best_face;
    if (best.kind == PlaneFeature::FaceA || best.kind == PlaneFeature::FaceB) best_face = best;
    sat_search(a, b, best, best_face, cutoff, r);
    if (best.s > cutoff) {
      store(cache, best);
      return early(best);
    }
    if (!(best.s > 0.0)) {
      // An edge pair lying in two (nearly) parallel faces ties with the face axis; its
      // cross-product normal carries eps / sin(crossing angle) of rounding. On a near
      // tie keep whichever normal achieves more when scanned (the face on equality).
      if (best.kind == PlaneFeature::EdgeEdge && best_face.s >= best.s - kTieRescan * pair_length(a, b) &&
          evaluate_axis(a, b, best_face.n).s >= evaluate_axis(a, b, best.n).s)
        best = best_face;
      store(cache, best);
      const CommonPlaneResult out = finish(best);
      // A certificate costs a second pass over the SAT's bounds: made only for a pair
      // that kept its facet from the last step, the kind that keeps it for many more.
      if (facet_start && best.kind == start.kind && best.index_a == start.index_a && best.index_b == start.index_b)
        make_certificate(a, b, best, out.gap, cache.certificate);
      return out;
    }
    // A facet separates them: the distance needs GJK, seeded at that facet's support pair.
    // Its value is replaced by the scanned one (an edge-pair value n.(q - p) can exceed
    // s(n) by rounding), so that GJK's scanned values compete on equal terms.
    const AxisValue av = evaluate_axis(a, b, best.n);
    best.s = av.s;
    go = gjk(a, b, single_vertex(a, b, av.ia, av.ib), cutoff);
    r.gjk_iterations += go.iterations;
    offer(best, go.s, go.n, PlaneFeature::Simplex, -1, -1);
    if (go.early_out) {
      store_simplex(cache, go.n, go.simplex);
      return early(best);
    }
  }

  // 4. Apart: the best of the facet/start axis, GJK's directions and the final link
  //    polished. (The best lower bound may come from an earlier, non-final simplex whose
  //    direction is off by far more than its small loss in s suggests: only the final
  //    link is the closest point.)
  Vec3 np;
  if (go.v.squaredNorm() > 0.0 && polish_normal(a, b, go.simplex, go.v.normalized(), np)) {
    const double s = evaluate_axis(a, b, np).s;
    if (s >= best.s) {
      best.s = s;
      best.n = np;
      best.kind = PlaneFeature::Simplex;
    }
  }
  store_simplex(cache, best.n, go.simplex);
  return finish(best);
}

}  // namespace
}  // namespace cp_detail

double plane_separation(const PolyhedronView& a, const PolyhedronView& b, const Vec3& n) {
  return cp_detail::evaluate_axis(a, b, n).s;
}

CommonPlaneResult find_common_plane(const PolyhedronView& a, const PolyhedronView& b,
                                    CommonPlaneCache& cache) {
  return cp_detail::solve(a, b, cache, cp_detail::kInf);
}

bool collide_polyhedra(const PolyhedronView& a, const PolyhedronView& b, double margin,
                       CommonPlaneCache& cache, ContactManifold& out, CommonPlaneResult* plane) {
  out.count = 0;
  const CommonPlaneResult r = cp_detail::solve(a, b, cache, margin);
  if (plane != nullptr) *plane = r;
  if (r.early_out || r.gap > margin) return false;
  cp_detail::build_manifold(a, b, r.normal, out);
  return out.count > 0;
}

}  // namespace ratchet
