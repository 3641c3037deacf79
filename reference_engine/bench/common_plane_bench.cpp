// Narrow phase by the Common Plane method on typical touching pairs of the paper's
// particles (20 vertices on an ellipsoid 1 : 0.95 : 0.9, r in [0.5, 1]), cold and
// warm started. A warm call sees the cache of the same pair one quasi-static step
// earlier (pose nudged by 1e-4 rad and 1e-4 r).
//
//   common_plane_bench --benchmark_filter=CommonPlane
//
// Argument: 0 = mixed pairs, 1 = overlapping only, 2 = apart only (|gap| <= 1e-3).
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <vector>

#include "ratchet/contact/common_plane.hpp"
#include "ratchet/core/random.hpp"
#include "ratchet/geometry/particle_generator.hpp"

namespace {

using namespace ratchet;

struct Body {
  ConvexPolyhedron shape;
  std::vector<Vec3> wv;
  PolyhedronView view;
  void place(const Vec3& c, const Mat3& R) {
    wv.resize(shape.vertices.size());
    for (std::size_t i = 0; i < wv.size(); ++i) wv[i] = c + R * shape.vertices[i];
    view.shape = &shape;
    view.world_vertices = wv.data();
    view.center = c;
    view.R = R;
    view.scale = 1.0;
  }
};

struct Pair {
  std::unique_ptr<Body> a, b;
  CommonPlaneCache previous;  // cache after the previous step
};

// Pairs touching with |gap| in [1e-6, 1e-3] (log-uniform), of the requested sign.
std::vector<Pair>& pairs(int kind) {
  static std::vector<Pair> sets[3];
  std::vector<Pair>& set = sets[kind];
  if (!set.empty()) return set;
  Rng rng(42 + static_cast<unsigned>(kind));
  const EllipsoidParticleSpec spec;  // the paper's particle, 20 vertices
  while (set.size() < 512) {
    Pair p;
    p.a = std::make_unique<Body>();
    p.b = std::make_unique<Body>();
    p.a->shape = generate_ellipsoid_particle(spec, rng).shape;
    p.b->shape = generate_ellipsoid_particle(spec, rng).shape;
    const Vec3 cb(uniform(rng, -8.0, 8.0), uniform(rng, -8.0, 8.0), uniform(rng, 0.0, 16.0));
    const Mat3 ra = uniform_rotation(rng).toRotationMatrix();
    p.b->place(cb, uniform_rotation(rng).toRotationMatrix());
    const Vec3 n = uniform_unit_vector(rng);
    p.a->place(cb + 2.0 * n, ra);
    double sign = uniform01(rng) < 0.5 ? -1.0 : 1.0;
    if (kind == 1) sign = -1.0;
    if (kind == 2) sign = 1.0;
    const double g = sign * std::pow(10.0, uniform(rng, -6.0, -3.0));
    // Slide along the exact common-plane normal to the target gap (setup only).
    for (int it = 0; it < 3; ++it) {
      CommonPlaneCache c;
      const CommonPlaneResult r = find_common_plane(p.a->view, p.b->view, c);
      p.a->place(p.a->view.center + r.normal * (g - r.gap), ra);
    }
    // The previous step: the pose 1e-4 away.
    const Vec3 c_now = p.a->view.center;
    const Mat3 dR = Eigen::AngleAxisd(1e-4, uniform_unit_vector(rng)).toRotationMatrix();
    p.a->place(c_now + 1e-4 * uniform_unit_vector(rng), dR.transpose() * ra);
    find_common_plane(p.a->view, p.b->view, p.previous);
    p.a->place(c_now, ra);
    CommonPlaneCache c;
    const CommonPlaneResult r = find_common_plane(p.a->view, p.b->view, c);
    if ((kind == 1 && r.gap >= 0.0) || (kind == 2 && r.gap <= 0.0)) continue;
    set.push_back(std::move(p));
  }
  return set;
}

void report(benchmark::State& state, long iterations, long pair_tests, long calls) {
  state.counters["iterations"] = static_cast<double>(iterations) / static_cast<double>(calls);
  state.counters["gauss_tests"] = static_cast<double>(pair_tests) / static_cast<double>(calls);
}

void BM_CommonPlane_Cold(benchmark::State& state) {
  auto& set = pairs(static_cast<int>(state.range(0)));
  std::size_t i = 0;
  long it = 0, pt = 0, calls = 0;
  for (auto _ : state) {
    Pair& p = set[i];
    CommonPlaneCache cache;
    const CommonPlaneResult r = find_common_plane(p.a->view, p.b->view, cache);
    benchmark::DoNotOptimize(r.gap);
    it += r.iterations();
    pt += r.sat_edge_pairs;
    ++calls;
    i = (i + 1) % set.size();
  }
  report(state, it, pt, calls);
}

void BM_CommonPlane_Warm(benchmark::State& state) {
  auto& set = pairs(static_cast<int>(state.range(0)));
  std::size_t i = 0;
  long it = 0, pt = 0, calls = 0;
  for (auto _ : state) {
    Pair& p = set[i];
    CommonPlaneCache cache = p.previous;
    const CommonPlaneResult r = find_common_plane(p.a->view, p.b->view, cache);
    benchmark::DoNotOptimize(r.gap);
    it += r.iterations();
    pt += r.sat_edge_pairs;
    ++calls;
    i = (i + 1) % set.size();
  }
  report(state, it, pt, calls);
}

// Plane plus contact manifold (margin 0.01), warm: what the engine's detect phase calls.
void BM_CollidePolyhedra_Warm(benchmark::State& state) {
  auto& set = pairs(static_cast<int>(state.range(0)));
  std::size_t i = 0;
  for (auto _ : state) {
    Pair& p = set[i];
    CommonPlaneCache cache = p.previous;
    ContactManifold m;
    benchmark::DoNotOptimize(collide_polyhedra(p.a->view, p.b->view, 0.01, cache, m));
    benchmark::DoNotOptimize(m.count);
    i = (i + 1) % set.size();
  }
}

// The cache copy alone, to subtract from the warm figures.
void BM_CacheCopy(benchmark::State& state) {
  auto& set = pairs(0);
  std::size_t i = 0;
  for (auto _ : state) {
    CommonPlaneCache cache = set[i].previous;
    benchmark::DoNotOptimize(cache);
    i = (i + 1) % set.size();
  }
}

BENCHMARK(BM_CommonPlane_Cold)->Arg(0)->Arg(1)->Arg(2);
BENCHMARK(BM_CommonPlane_Warm)->Arg(0)->Arg(1)->Arg(2);
BENCHMARK(BM_CollidePolyhedra_Warm)->Arg(0)->Arg(1)->Arg(2);
BENCHMARK(BM_CacheCopy);

}  // namespace
