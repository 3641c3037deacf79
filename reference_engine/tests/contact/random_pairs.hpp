// Random pairs of posed polyhedra for the tests of the Common Plane files (tests only):
// the paper's particle generator in three shape families, and pose generators for the
// contact situations the narrow phase must get right (deep overlap, near touching,
// parallel faces and edges, vertex on face, vertex on vertex).
#pragma once

#include <cmath>
#include <cstring>
#include <vector>

#include "ratchet/contact/polyhedron_view.hpp"
#include "ratchet/core/random.hpp"

namespace ratchet::test {

inline double angle_between(const Vec3& u, const Vec3& v) { return std::atan2(u.cross(v).norm(), u.dot(v)); }

// A polyhedron posed in the world with its own vertex storage.
class Posed {
 public:
  explicit Posed(const ConvexPolyhedron& s) : shape_(&s) {}
  Posed(const Posed&) = delete;
  Posed& operator=(const Posed&) = delete;
  void place(const Vec3& c, const Mat3& R, double scale = 1.0) {
    wv_.resize(shape_->vertices.size());
    for (std::size_t i = 0; i < wv_.size(); ++i) wv_[i] = c + scale * (R * shape_->vertices[i]);
    view_.shape = shape_;
    view_.world_vertices = wv_.data();
    view_.center = c;
    view_.R = R;
    view_.scale = scale;
  }
  void translate(const Vec3& t) { place(view_.center + t, view_.R, view_.scale); }
  const PolyhedronView& view() const { return view_; }
  const Vec3& center() const { return view_.center; }
  const Mat3& R() const { return view_.R; }
  const Vec3& vertex(int i) const { return wv_[static_cast<std::size_t>(i)]; }
  double radius() const { return view_.scale * shape_->bounding_radius; }
  const ConvexPolyhedron& shape() const { return *shape_; }

 private:
  const ConvexPolyhedron* shape_;
  std::vector<Vec3> wv_;
  PolyhedronView view_;
};

// ---------------------------------------------------------------------------------
// Shapes: the paper's generator (20 vertices, r in [0.5, 1]) plus flat and elongated.
// ---------------------------------------------------------------------------------

enum Family { kEllipsoid = 0, kFlat = 1, kElongated = 2 };
const char* const kFamilyName[] = {"ellipsoid(1,.95,.9)", "flat(1,1,.2)", "elongated(1,.3,.3)"};

// A shape of the pool (64 per family, made once): ellipsoid 60 %, flat and elongated
// 20 % each; `family` receives which.
const ConvexPolyhedron& pick_shape(Rng& rng, int& family);

inline Mat3 random_rotation(Rng& rng) { return uniform_rotation(rng).toRotationMatrix(); }

// A small signed gap: 10 % exactly touching, else +-10^U(-7,-3).
double small_gap(Rng& rng);

// ---------------------------------------------------------------------------------
// Pose generators. B is placed anywhere in a bed-sized box, A relative to it.
// ---------------------------------------------------------------------------------

enum Category { kDeep, kRandom, kNearTouch, kFaceFace, kEdgeEdge, kVertexFace, kVertexVertex, kCategories };
const char* const kCategoryName[] = {"deep overlap", "random distance", "near touching", "face-face parallel",
                                     "edge-edge parallel", "vertex on face", "vertex on vertex"};

// Moves A along n so that s(n) = g (s by the oracle's full scans).
void set_separation(Posed& A, const Posed& B, const Vec3& n, double g);

// Places B and A for one pose of category cat.
void generate_pose(Category cat, Rng& rng, Posed& A, Posed& B);

// A pose step of a quasi-static bed: rotation ~1e-4 rad, translation ~1e-4 r, and the
// thermal growth of one step (scale x (1 + growth); the paper's 1 % over a half cycle).
void nudge(Posed& p, Rng& rng, double size, double growth = 0.0);

// A rigid perturbation of p about its centre: rotation by `angle` about a random axis,
// translation by `shift` in a random direction.
void perturb(Posed& p, Rng& rng, double angle, double shift, double scale);

inline bool same_bits(double x, double y) { return std::memcmp(&x, &y, sizeof(double)) == 0; }
inline bool same_bits(const Vec3& x, const Vec3& y) { return std::memcmp(x.data(), y.data(), 3 * sizeof(double)) == 0; }

}  // namespace ratchet::test
