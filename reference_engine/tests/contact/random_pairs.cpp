// Random pairs of posed polyhedra for the Common Plane tests (random_pairs.hpp).
#include "random_pairs.hpp"

#include <algorithm>
#include <cmath>

#include "ratchet/geometry/particle_generator.hpp"
#include "sat_oracle.hpp"

namespace ratchet::test {

namespace {

struct ShapePool {
  std::vector<ConvexPolyhedron> shapes[3];
};

const ShapePool& shape_pool() {
  static const ShapePool pool = [] {
    ShapePool p;
    Rng rng(20240611);
    const Vec3 axes[3] = {Vec3(1.0, 0.95, 0.9), Vec3(1.0, 1.0, 0.2), Vec3(1.0, 0.3, 0.3)};
    for (int f = 0; f < 3; ++f) {
      EllipsoidParticleSpec spec;
      spec.vertices = 20;
      spec.axes = axes[f];
      for (int k = 0; k < 64; ++k) p.shapes[f].push_back(generate_ellipsoid_particle(spec, rng).shape);
    }
    return p;
  }();
  return pool;
}

}  // namespace

const ConvexPolyhedron& pick_shape(Rng& rng, int& family) {
  const double u = uniform01(rng);
  family = u < 0.6 ? kEllipsoid : (u < 0.8 ? kFlat : kElongated);
  const auto& list = shape_pool().shapes[family];
  return list[static_cast<std::size_t>(rng() % list.size())];
}

double small_gap(Rng& rng) {
  if (uniform01(rng) < 0.1) return 0.0;
  const double mag = std::pow(10.0, uniform(rng, -7.0, -3.0));
  return uniform01(rng) < 0.5 ? -mag : mag;
}

void set_separation(Posed& A, const Posed& B, const Vec3& n, double g) {
  A.translate(n * (g - oracle_separation(A.view(), B.view(), n)));
}

void generate_pose(Category cat, Rng& rng, Posed& A, Posed& B) {
  // Thermal scales: the bed's own range is [1, 1.01]; [0.98, 1.02] tests any s_p.
  const double sa = uniform(rng, 0.98, 1.02), sb = uniform(rng, 0.98, 1.02);
  const Vec3 cb(uniform(rng, -8.0, 8.0), uniform(rng, -8.0, 8.0), uniform(rng, 0.0, 16.0));
  B.place(cb, random_rotation(rng), sb);
  const double rsum = sa * A.shape().bounding_radius + B.radius();
  switch (cat) {
    case kDeep: {
      A.place(cb + uniform_unit_vector(rng) * uniform(rng, 0.0, 0.5 * rsum), random_rotation(rng), sa);
      break;
    }
    case kRandom: {
      A.place(cb + uniform_unit_vector(rng) * uniform(rng, 0.0, 1.2 * rsum), random_rotation(rng), sa);
      break;
    }
    case kNearTouch: {
      // Apart along n first, then slid along the exact shortest link to the target gap
      // (moving along the link keeps it the link; into overlap the depth is <= |g|).
      const Vec3 n = uniform_unit_vector(rng);
      A.place(cb + n * rsum, random_rotation(rng), sa);
      set_separation(A, B, n, 0.01);
      const OracleResult o = oracle_common_plane(A.view(), B.view());
      A.translate(o.normal * (small_gap(rng) - o.gap));
      break;
    }
    case kFaceFace: {
      // A face of A exactly anti-parallel to a face of B, centred over it with an offset.
      const int fb = static_cast<int>(rng() % B.shape().faces.size());
      const int fa = static_cast<int>(rng() % A.shape().faces.size());
      const Vec3 m = B.view().face_normal(fb);
      // FromTwoVectors of nearly opposite vectors goes through an SVD and is orthonormal
      // only to ~1e-12: renormalise the quaternion, as the engine's bodies are.
      const Quat align = Quat::FromTwoVectors(A.shape().face_normals[static_cast<std::size_t>(fa)], -m);
      const Mat3 R = (Quat(Eigen::AngleAxisd(uniform(rng, 0.0, 2.0 * M_PI), m)) * align).normalized().toRotationMatrix();
      auto centroid = [](const Posed& p, const std::vector<int>& face) {
        Vec3 c = Vec3::Zero();
        for (int v : face) c += p.vertex(v);
        return Vec3(c / static_cast<double>(face.size()));
      };
      A.place(Vec3::Zero(), R, sa);
      const Vec3 lateral = uniform_unit_vector(rng) * uniform(rng, 0.0, 0.3 * B.radius());
      A.translate(centroid(B, B.shape().faces[static_cast<std::size_t>(fb)]) -
                  centroid(A, A.shape().faces[static_cast<std::size_t>(fa)]) + (lateral - m * m.dot(lateral)));
      const double g = uniform01(rng) < 0.2 ? -uniform(rng, 0.0, 0.05) : small_gap(rng);
      set_separation(A, B, m, g);
      break;
    }
    case kEdgeEdge: {
      // An edge of A exactly parallel to an edge of B, each the support of its body along
      // the plane normal n (n inside both Gauss-map arcs), overlapping along their length.
      const int eb = static_cast<int>(rng() % B.shape().edges.size());
      const int ea = static_cast<int>(rng() % A.shape().edges.size());
      const auto& fb = B.shape().edge_faces[static_cast<std::size_t>(eb)];
      const auto& fa = A.shape().edge_faces[static_cast<std::size_t>(ea)];
      const auto& vb = B.shape().edges[static_cast<std::size_t>(eb)];
      const auto& va = A.shape().edges[static_cast<std::size_t>(ea)];
      const Vec3 nb = (B.view().face_normal(fb[0]) + B.view().face_normal(fb[1])).normalized();
      Vec3 tb = (B.vertex(vb[1]) - B.vertex(vb[0]));
      tb = (tb - nb * nb.dot(tb)).normalized();
      if (uniform01(rng) < 0.5) tb = -tb;
      const Vec3 na = (A.shape().face_normals[static_cast<std::size_t>(fa[0])] + A.shape().face_normals[static_cast<std::size_t>(fa[1])]).normalized();
      Vec3 ta = A.shape().vertices[static_cast<std::size_t>(va[1])] - A.shape().vertices[static_cast<std::size_t>(va[0])];
      ta = (ta - na * na.dot(ta)).normalized();
      Mat3 body, world;
      body << ta, na, ta.cross(na);
      world << tb, -nb, tb.cross(-nb);
      A.place(Vec3::Zero(), world * body.transpose(), sa);
      const Vec3 mid_b = 0.5 * (B.vertex(vb[0]) + B.vertex(vb[1]));
      const Vec3 mid_a = 0.5 * (A.vertex(va[0]) + A.vertex(va[1]));
      const double len = std::min((B.vertex(vb[1]) - B.vertex(vb[0])).norm(), (A.vertex(va[1]) - A.vertex(va[0])).norm());
      A.translate(mid_b - mid_a + tb * uniform(rng, -0.3, 0.3) * len);
      set_separation(A, B, nb, small_gap(rng));
      break;
    }
    case kVertexFace: {
      // A's lowest vertex along -m over a point inside B's face (between centroid and a corner).
      const int fb = static_cast<int>(rng() % B.shape().faces.size());
      const auto& face = B.shape().faces[static_cast<std::size_t>(fb)];
      const Vec3 m = B.view().face_normal(fb);
      Vec3 c = Vec3::Zero();
      for (int v : face) c += B.vertex(v);
      c /= static_cast<double>(face.size());
      const Vec3 target = c + uniform(rng, 0.0, 0.8) * (B.vertex(face[rng() % face.size()]) - c);
      A.place(Vec3::Zero(), random_rotation(rng), sa);
      int lowest = 0;
      for (int i = 1; i < static_cast<int>(A.shape().vertices.size()); ++i)
        if (m.dot(A.vertex(i)) < m.dot(A.vertex(lowest))) lowest = i;
      A.translate(target - A.vertex(lowest));
      set_separation(A, B, m, uniform01(rng) < 0.2 ? -uniform(rng, 0.0, 0.05) : small_gap(rng));
      break;
    }
    case kVertexVertex: {
      // The support vertices of A and B along a random n put tip to tip.
      const Vec3 n = uniform_unit_vector(rng);
      A.place(Vec3::Zero(), random_rotation(rng), sa);
      int ia = 0, ib = 0;
      for (int i = 1; i < static_cast<int>(A.shape().vertices.size()); ++i)
        if (n.dot(A.vertex(i)) < n.dot(A.vertex(ia))) ia = i;
      for (int j = 1; j < static_cast<int>(B.shape().vertices.size()); ++j)
        if (n.dot(B.vertex(j)) > n.dot(B.vertex(ib))) ib = j;
      A.translate(B.vertex(ib) - A.vertex(ia) + n * small_gap(rng));
      break;
    }
    default:
      break;
  }
}

void nudge(Posed& p, Rng& rng, double size, double growth) {
  const Mat3 dR = Eigen::AngleAxisd(size, uniform_unit_vector(rng)).toRotationMatrix();
  p.place(p.center() + uniform_unit_vector(rng) * size, dR * p.R(), p.view().scale * (1.0 + growth));
}

void perturb(Posed& p, Rng& rng, double angle, double shift, double scale) {
  const Mat3 R = (Quat(Eigen::AngleAxisd(angle, uniform_unit_vector(rng))) * Quat(p.R())).normalized().toRotationMatrix();
  p.place(p.center() + uniform_unit_vector(rng) * shift, R, scale);
}

}  // namespace ratchet::test
