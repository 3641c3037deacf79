// reuse_audit: what manifold reuse (solver.manifold_reuse) changes on a real bed. Loads a
// scene and its packing, sets the reuse bound, steps the run's first STEPS steps with
// every replayed pair also built anew (the ReuseAudit test hook), and prints how many
// polyhedron pairs were replayed and how far the deepest replayed gap strayed from the
// fresh one, absolutely and per unit of the pair's motion bound. docs/performance.md
// used it.
//
//   reuse_audit SCENE PACKING STEPS BOUND [KEY=VALUE ...]
//
// Exit status 0 when no replayed empty pair had a contact and every error is within
// 2 * BOUND (the stated bound, contact/manifold_reuse.hpp), 1 otherwise, 2 on bad
// arguments or an unreadable scene or packing.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "ratchet/run/packing.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/world/test_hooks.hpp"
#include "ratchet/world/world.hpp"

int main(int argc, char** argv) {
  using namespace ratchet;
  if (argc < 5) {
    std::fprintf(stderr, "usage: reuse_audit SCENE PACKING STEPS BOUND [KEY=VALUE ...]\n");
    return 2;
  }
  char* end = nullptr;
  const long steps = std::strtol(argv[3], &end, 10);
  if (*end != '\0' || steps <= 0) {
    std::fprintf(stderr, "reuse_audit: STEPS: expected a positive integer, got '%s'\n", argv[3]);
    return 2;
  }
  const std::string bound = argv[4];
  std::vector<std::string> sets = {"solver.manifold_reuse=" + bound, "solver.threads=1"};
  for (int k = 5; k < argc; ++k) sets.emplace_back(argv[k]);
  ReuseAudit audit;
  long replayed_pairs = 0, built_pairs = 0;
  double delta = 0.0;
  try {
    const SceneDef scene = load_scene(argv[1], sets);
    delta = scene.solver.manifold_reuse;
    World world(scene);
    load_packing(argv[2], world);
    test_hooks().reuse_audit = &audit;
    for (long k = 0; k < steps; ++k) {
      world.step();
      replayed_pairs += world.stats().manifolds_replayed;
      built_pairs += world.stats().manifolds_built;
    }
    test_hooks().reuse_audit = nullptr;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "reuse_audit: %s\n", e.what());
    return 2;
  }
  const double share = replayed_pairs + built_pairs > 0
                           ? static_cast<double>(replayed_pairs) / static_cast<double>(replayed_pairs + built_pairs)
                           : 0.0;
  std::printf("bound %g: %ld steps, %ld pair-steps replayed, %ld built (%.1f %% replayed); "
              "deepest gap off by at most %.3g (%.3g of the bound), at most %.3g x the pair's motion; "
              "%ld replayed empty pairs had a contact\n",
              delta, steps, replayed_pairs, built_pairs, 100.0 * share, audit.max_gap_error,
              delta > 0 ? audit.max_gap_error / delta : 0.0, audit.max_error_per_motion, audit.empty_violations);
  return audit.empty_violations == 0 && audit.max_gap_error <= 2.0 * delta ? 0 : 1;
}
