// bed_trace: steps a cached step_bench bed and prints, per step, what sets the cost of a
// warm-started step: Gauss-Seidel sweeps, contact points, active ones, how many found
// their impulse of the last step (warm-start hits) and how many active ones did not,
// the overlaps (count, mean depth, deepest and its pair) and KE / peak KE of the pour; at the end the
// bodies carrying the most kinetic energy with their contacts (a body rocking on two
// contacts, or falling, keeps a bed from being static). docs/performance.md used it.
//
//   bed_trace N STATE_FILE STEPS [impulse|velocity|fixed10] [OUT_STATE]
//
// STATE_FILE: a cached bed of step_bench (io/state_file format, $RATCHET_BENCH_CACHE);
// OUT_STATE: write the state after the steps there (every 250 steps and at the end),
// with the cache's key and metadata, so that step_bench can time the rested bed.
// RATCHET_TRACE_BODY=i: after every step also body i's velocities and its contacts
// (partner, gap, lambda_n, |lambda_t|, normal, feature ids).
// Exit status 2 on bad arguments or an unreadable state file.
#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "bench_bed.hpp"
#include "ratchet/io/state_file.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/observe/energy.hpp"
#include "ratchet/world/world.hpp"

namespace {

using namespace ratchet;

int usage(const char* why) {
  std::fprintf(stderr, "bed_trace: %s\nusage: bed_trace N STATE_FILE STEPS [impulse|velocity|fixed10] [OUT_STATE]\n", why);
  return 2;
}

// A whole decimal int, nothing else (atoi would read "12x" as 12 and "x" as 0).
bool parse_int(const char* text, int& out) {
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || errno != 0 || v < INT_MIN || v > INT_MAX) return false;
  out = static_cast<int>(v);
  return true;
}

bool has_key(const std::vector<KeptImpulse>& kept, const ContactKey& key) {
  return std::binary_search(kept.begin(), kept.end(), KeptImpulse{key, Vec3::Zero()},
                            [](const KeptImpulse& x, const KeptImpulse& y) { return x.key < y.key; });
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4 || argc > 6) return usage("wrong number of arguments");
  int n = 0, steps = 0;
  const std::string mode = argc > 4 ? argv[4] : "impulse";
  if (!parse_int(argv[1], n) || !parse_int(argv[3], steps) || n <= 0 || steps <= 0)
    return usage("N and STEPS must be positive integers");
  if (mode != "impulse" && mode != "velocity" && mode != "fixed10") return usage("mode must be impulse, velocity or fixed10");
  StateFile file;
  try {
    file = read_state_file(argv[2]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bed_trace: %s\n", e.what());
    return 2;
  }
  const bool fixed10 = mode == "fixed10";
  const SceneDef scene = build_scene(bench::bed_scene(n, 1e-3, fixed10 ? 1e-300 : 1e-4, fixed10 ? 10 : 1000,
                                                      mode == "velocity" ? "velocity" : nullptr),
                                     "bed_trace");
  if (file.state.x.size() != scene.bodies.size()) return usage("the state file does not hold a bed of N bodies");
  World world(scene);
  world.mutable_state() = file.state;
  const double peak = file.meta.value("peak", 0.0);
  auto save = [&] {
    if (argc < 6) return;
    StateFile out = file;
    out.state = world.state();
    write_state_file(argv[5], out);
  };
  // RATCHET_TRACE_BODY=i: after every step, body i's velocities and its contacts.
  const char* watch_env = std::getenv("RATCHET_TRACE_BODY");
  int watch = -1;
  if (watch_env != nullptr && (!parse_int(watch_env, watch) || watch < 0 || watch >= static_cast<int>(file.state.x.size())))
    return usage("RATCHET_TRACE_BODY must be a body index of the bed (0 to N-1)");
  std::printf("step sweeps contacts active kept hits active_missed overlaps mean_overlap min_gap KE_over_peak min_gap_a min_gap_b\n");
  for (int k = 0; k < steps; ++k) {
    const std::vector<KeptImpulse> kept = world.state().impulses;
    world.step();
    int active = 0, hits = 0, missed = 0, overlaps = 0;
    double depth = 0.0, min_gap = 0.0;
    int min_a = -1, min_b = -1;  // the pair of the deepest overlap (b < 0: wall -1 - b)
    for (const SolverContact& c : world.contacts()) {
      const bool hit = has_key(kept, {c.a, c.b, c.geometry.feature_a, c.geometry.feature_b});
      hits += hit ? 1 : 0;
      if (c.lambda[0] > 0.0) {
        ++active;
        missed += hit ? 0 : 1;
      }
      if (c.geometry.gap < 0.0) {
        ++overlaps;
        depth -= c.geometry.gap;
      }
      if (c.geometry.gap < min_gap) {
        min_gap = c.geometry.gap;
        min_a = c.a;
        min_b = c.b;
      }
    }
    std::printf("%d %d %zu %d %zu %d %d %d %.3e %.3e %.3e %d %d\n", k, world.stats().iterations, world.contacts().size(),
                active, kept.size(), hits, missed, overlaps, overlaps > 0 ? depth / overlaps : 0.0, min_gap,
                peak > 0.0 ? kinetic_energy(world.scene(), world.state()) / peak : 0.0, min_a, min_b);
    if (watch >= 0) {
      const State& st = world.state();
      const auto w = static_cast<std::size_t>(watch);
      std::printf("#  body %d: v %.3e %.3e %.3e  w %.3e %.3e %.3e\n", watch, st.v[w].x(), st.v[w].y(), st.v[w].z(),
                  st.w[w].x(), st.w[w].y(), st.w[w].z());
      for (const SolverContact& c : world.contacts())
        if (c.a == watch || c.b == watch)
          std::printf("#    with %d: gap %.3e lambda_n %.3e |lambda_t| %.3e n %.3f %.3f %.3f features %d %d\n",
                      c.a == watch ? c.b : c.a, c.geometry.gap, c.lambda[0], std::hypot(c.lambda[1], c.lambda[2]),
                      c.geometry.normal.x(), c.geometry.normal.y(), c.geometry.normal.z(), c.geometry.feature_a,
                      c.geometry.feature_b);
    }
    if (k % 250 == 249) save();
  }
  save();
  // The bodies with the largest |v|^2 + |w|^2 (a ranking, not an energy).
  const State& s = world.state();
  std::vector<std::pair<double, int>> ranked;
  for (std::size_t i = 0; i < s.v.size(); ++i) ranked.emplace_back(s.v[i].squaredNorm() + s.w[i].squaredNorm(), static_cast<int>(i));
  std::sort(ranked.rbegin(), ranked.rend());
  std::printf("# fastest bodies: body |v| |w| x y z contacts active wall_active\n");
  for (std::size_t r = 0; r < std::min<std::size_t>(10, ranked.size()); ++r) {
    const int i = ranked[r].second;
    int contacts = 0, active = 0, wall = 0;
    for (const SolverContact& c : world.contacts())
      if (c.a == i || c.b == i) {
        ++contacts;
        if (c.lambda[0] > 0.0) {
          ++active;
          wall += c.b < 0 ? 1 : 0;
        }
      }
    const auto idx = static_cast<std::size_t>(i);
    std::printf("# %d %.2e %.2e %.2f %.2f %.2f %d %d %d\n", i, s.v[idx].norm(), s.w[idx].norm(), s.x[idx].x(),
                s.x[idx].y(), s.x[idx].z(), contacts, active, wall);
  }
  return 0;
}
