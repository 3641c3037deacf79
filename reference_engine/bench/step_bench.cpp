// One full World::step() of a SETTLED bed of the paper's polyhedra (20 vertices on an
// ellipsoid 1 : 0.95 : 0.9, r in [0.5, 1], mu = 0.5), warm started, solver tolerance
// 1e-4, h = 1e-3, split into detection and solve (World::timers().last_step), for
// N = 250 ... 8000 in a 16-sided cylinder whose radius grows with sqrt(N)
// (r_c = 5 sqrt(N / 250)), so the bed height (about 5.5) stays the same.
//
//   step_bench --benchmark_filter='Step/N:1000/threads:1/'   N = 1000, 1 thread
//   step_bench --benchmark_counters_tabular=true            all
//
// Arguments: N, OpenMP threads (omp_set_num_threads). Step: converged to 1e-4 (at most
// 1000 sweeps); StepV: the same with solver.criterion "velocity"; Step10: exactly 10
// sweeps per step, as a fixed-iteration engine does (tolerance 1e-300: never met), for
// comparison with such engines.
//
// The bed is poured once per N (lattice release) and settled with a cheap solver
// (h = 5e-3, tolerance 1e-3, at most 30 sweeps per step: settling at tolerance 1e-4
// costs hundreds of sweeps per step, hours for the larger N) until the kinetic energy
// is below 1e-8 of its peak, or for at most 30 time units after the top layer could
// have landed. Then steps of the benchmark's own scene (h = 1e-3, tolerance 1e-4) bring
// it to rest and rebuild the warm start: the first 200 with every velocity zeroed after
// the step (kinetic damping, see bring_to_rest), then until KE < 1e-9 of the peak and a
// step needs at most 10 sweeps (a static bed, warm started, needs a few) for 100 steps
// in a row, at least 300 and at most 2000 steps in all (RATCHET_BENCH_REST_STEPS=K caps them at K;
// RATCHET_BENCH_QUENCH_STEPS=Q quenches Q steps instead of 200;
// RATCHET_BENCH_REST_CRITERION=velocity rests with solver.criterion "velocity"). A cached
// state goes through the same rest again; RATCHET_BENCH_REST_STEPS=1
// RATCHET_BENCH_QUENCH_STEPS=0 times a cached bed as it is (one step, not saved).
//
// The state (poses, velocities, kept impulses and common planes) is cached in
// $RATCHET_BENCH_CACHE (default /tmp/ratchet_step_bench, io/state_file format), keyed
// by N and the generated bodies (FNV-1a of the scene hash and every body's mass,
// bounding radius and initial position, so a change of the generator invalidates it),
// so later runs start from it at once. The settling reached is reported in the counters
// (KE_ratio: kinetic energy / its peak during the pour, at the end of the timed steps)
// and on stderr. Each timed iteration is one step of that bed, restarted from the
// rested state for every benchmark run (so 1 and 2 threads step the same bed); 5
// untimed steps come first. Figures and commands: docs/performance.md.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <sys/stat.h>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_bed.hpp"
#include "ratchet/io/state_file.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/observe/energy.hpp"
#include "ratchet/world/world.hpp"

namespace {

using namespace ratchet;
using nlohmann::json;

constexpr double kBenchDt = 1e-3;    // h of the timed steps
constexpr double kSettleDt = 5e-3;   // h of the pour
constexpr double kSettleTolerance = 1e-3;
constexpr int kSettleMaxSweeps = 30;
constexpr double kSettleAfterLanding = 30.0;  // cap on the settling time after landing
constexpr double kKeRatio = 1e-8;    // settled: KE < kKeRatio * peak KE
constexpr int kAdaptSteps = 300;     // steps of the benchmark's scene before the state is cached
constexpr int kQuenchSteps = 200;    // ... of which the first are quenched (bring_to_rest)
constexpr int kMaxRestSteps = 2000;  // ... at most, until at rest:
constexpr double kRestKeRatio = 1e-9;  // KE < kRestKeRatio * peak and
constexpr int kRestSweeps = 10;        // at most this many sweeps in the step,
constexpr int kRestWindow = 100;       // for this many steps in a row after the quench
constexpr int kCacheVersion = 2;  // 2: io/state_file

using bench::bed_scene;
using bench::cylinder_radius;

struct SettleInfo {
  double peak = 0.0;           // peak kinetic energy of the pour
  double ke_ratio = 0.0;       // KE / peak KE when the pour stopped
  double settle_time = 0.0;    // simulated time of the pour and settling
  double wall_seconds = 0.0;   // wall time it took (0 when loaded from the cache)
  bool from_cache = false;
};

// --- cache file: io/state_file (the format of packings), the settle figures in its
// metadata ----------------------------------------------------------------------------

std::string cache_path(int n, const std::string& hash) {
  const char* env = std::getenv("RATCHET_BENCH_CACHE");
  const std::string dir = env != nullptr && *env != '\0' ? env : "/tmp/ratchet_step_bench";
  ::mkdir(dir.c_str(), 0755);
  return dir + "/bed_" + std::to_string(n) + "_" + hash + ".state";
}

bool load_state(const std::string& path, std::size_t n, const std::string& hash, State& s, SettleInfo& info) {
  std::ifstream probe(path, std::ios::binary);
  if (!probe) return false;
  try {
    const StateFile f = read_state_file(path);
    if (f.key != hash || f.state.x.size() != n || f.meta.value("cache_version", 0) != kCacheVersion) return false;
    s = f.state;
    info.ke_ratio = f.meta.at("ke_ratio").get<double>();
    info.settle_time = f.meta.at("settle_time").get<double>();
    info.wall_seconds = f.meta.at("wall_seconds").get<double>();
    info.peak = f.meta.at("peak").get<double>();
    info.from_cache = true;
    return true;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "step_bench: ignoring the cache: %s\n", e.what());
    return false;
  }
}

void save_state(const std::string& path, const std::string& hash, const State& s, const SettleInfo& info) {
  StateFile f;
  f.key = hash;
  f.state = s;
  f.meta = json{{"cache_version", kCacheVersion}, {"ke_ratio", info.ke_ratio}, {"settle_time", info.settle_time},
                {"wall_seconds", info.wall_seconds}, {"peak", info.peak}};
  write_state_file(path, f);
}

// Pours the bed at kSettleDt and settles it; returns the state at the end.
State pour_and_settle(int n, SettleInfo& info) {
  const SceneDef scene = build_scene(bed_scene(n, kSettleDt, kSettleTolerance, kSettleMaxSweeps), "step_bench");
  World world(scene);
  double z_top = 0.0;
  for (const BodyDef& b : scene.bodies) z_top = std::max(z_top, b.position.z());
  const double t_landed = std::sqrt(2.0 * z_top);  // g = 1
  const double t_cap = t_landed + kSettleAfterLanding;
  const auto wall0 = std::chrono::steady_clock::now();
  double peak = 0.0, ke = 0.0;
  std::fprintf(stderr, "step_bench: pouring N = %d into r_c = %.3f (top site z = %.1f, landed by t = %.1f)\n", n,
               cylinder_radius(n), z_top, t_landed);
  while (world.state().t < t_cap) {
    world.step();
    ke = kinetic_energy(world.scene(), world.state());
    peak = std::max(peak, ke);
    if (world.state().t > t_landed && ke < kKeRatio * peak) break;
    if (world.state().step % 250 == 0)
      std::fprintf(stderr, "  N = %d  t = %6.2f  KE/peak = %.2e  contacts %d  sweeps %d  (%.0f s)\n", n,
                   world.state().t, ke / peak, world.stats().contacts, world.stats().iterations,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count());
  }
  info.peak = peak;
  info.ke_ratio = ke / peak;
  info.settle_time = world.state().t;
  info.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  std::fprintf(stderr, "step_bench: N = %d %s at t = %.2f (KE/peak = %.2e) in %.0f s\n", n,
               info.ke_ratio < kKeRatio ? "settled" : "NOT fully settled (cap)", info.settle_time, info.ke_ratio,
               info.wall_seconds);
  return world.state();
}

// Identifies the generated bed: the scene and the bodies the generator made from it.
std::string bed_key(const SceneDef& scene) {
  std::string bytes = scene.hash;
  for (const BodyDef& b : scene.bodies) {
    const double d[5] = {b.mass, b.bounding_radius, b.position.x(), b.position.y(), b.position.z()};
    bytes.append(reinterpret_cast<const char*>(d), sizeof d);
  }
  return fnv1a_hex(bytes);
}

struct Bed {
  std::unique_ptr<World> world;    // tolerance 1e-4, at most 1000 sweeps
  std::unique_ptr<World> fixed10;  // exactly 10 sweeps per step (no tolerance reached)
  std::unique_ptr<World> by_velocity;  // tolerance 1e-4 on solver.criterion "velocity"
  SettleInfo info;
  State rested;  // the state every benchmark run starts from
};

// Steps the bench world until the bed is at rest (see the top); returns the steps taken.
// The first `quench` steps zero every velocity after the step (kinetic damping): the
// overlaps left by the cheap pour are closed by the gap relaxation, which at h = 1e-3
// pushes bodies apart at p_gap g / h and keeps a bed of 500 or more stirring for
// thousands of steps; quenched, those kicks do not accumulate into motion.
int bring_to_rest(World& world, const SettleInfo& info, int min_steps, int quench) {
  const char* env = std::getenv("RATCHET_BENCH_REST_STEPS");  // cap for a quick look; default kMaxRestSteps
  const int max_steps = env != nullptr && *env != '\0' ? std::max(1, std::atoi(env)) : kMaxRestSteps;
  const auto wall0 = std::chrono::steady_clock::now();
  int k = 0, resting = 0;
  while (k < max_steps) {
    world.step();
    ++k;
    if (k % 250 == 0)  // progress: a long rest of a large bed takes many minutes
      std::fprintf(stderr, "  resting: step %d, KE/peak = %.2e, %d sweeps (%.0f s)\n", k,
                   kinetic_energy(world.scene(), world.state()) / info.peak, world.stats().iterations,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count());
    if (k <= quench) {
      State& s = world.mutable_state();
      for (Vec3& v : s.v) v.setZero();
      for (Vec3& w : s.w) w.setZero();
      continue;
    }
    // At rest for kRestWindow steps in a row: right after the quench every bed looks
    // static, and bodies the quench stopped short of equilibrium move off only later.
    const bool at_rest = kinetic_energy(world.scene(), world.state()) < kRestKeRatio * info.peak && world.stats().iterations <= kRestSweeps;
    resting = at_rest ? resting + 1 : 0;
    if (k >= min_steps && resting >= kRestWindow) break;
  }
  return k;
}

// The settled bed of N, built once per process (and once per cache).
Bed& settled_bed(int n) {
  static std::map<int, Bed> beds;
  auto it = beds.find(n);
  if (it != beds.end()) return it->second;
  Bed bed;
  const SceneDef scene = build_scene(bed_scene(n, kBenchDt, 1e-4, 1000), "step_bench");
  bed.world = std::make_unique<World>(scene);
  const std::string key = bed_key(scene);
  const std::string path = cache_path(n, key);
  int min_steps = 1;
  if (!load_state(path, scene.bodies.size(), key, bed.world->mutable_state(), bed.info)) {
    State s = pour_and_settle(n, bed.info);
    // Continue at the benchmark's h: the kept impulses scale with h (lambda = F h).
    for (KeptImpulse& k : s.impulses) k.impulse *= kBenchDt / kSettleDt;
    bed.world->mutable_state() = s;
    min_steps = kAdaptSteps;
    save_state(path, key, bed.world->state(), bed.info);  // the pour, before resting
  }
  const auto wall0 = std::chrono::steady_clock::now();
  // RATCHET_BENCH_QUENCH_STEPS=Q: quench Q steps instead (a longer kinetic damping lets a
  // large bed find a static configuration; the cache keeps the result).
  const char* quench_env = std::getenv("RATCHET_BENCH_QUENCH_STEPS");
  const int quench = quench_env != nullptr && *quench_env != '\0' ? std::max(0, std::atoi(quench_env)) : kQuenchSteps;
  // RATCHET_BENCH_REST_CRITERION=velocity: rest with solver.criterion "velocity" (fewer
  // sweeps per step on a large bed, so a long rest costs less; the state is the same kind).
  bed.by_velocity = std::make_unique<World>(build_scene(bed_scene(n, kBenchDt, 1e-4, 1000, "velocity"), "step_bench"));
  const char* crit_env = std::getenv("RATCHET_BENCH_REST_CRITERION");
  const bool rest_by_velocity = crit_env != nullptr && std::string(crit_env) == "velocity";
  World& rest_world = rest_by_velocity ? *bed.by_velocity : *bed.world;
  if (rest_by_velocity) rest_world.mutable_state() = bed.world->state();
  const int steps = bring_to_rest(rest_world, bed.info, std::max(min_steps, quench + 1), quench);
  if (rest_by_velocity) bed.world->mutable_state() = rest_world.state();
  std::fprintf(stderr,
               "step_bench: N = %d, %d steps at h = %g, tolerance 1e-4: KE/peak = %.2e, %d sweeps in the last (%.0f s)\n",
               n, steps, kBenchDt, kinetic_energy(rest_world.scene(), rest_world.state()) / bed.info.peak, rest_world.stats().iterations,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count());
  if (steps > 1) {
    save_state(path, key, bed.world->state(), bed.info);
    std::fprintf(stderr, "step_bench: cached %s\n", path.c_str());
  }
  bed.rested = bed.world->state();
  bed.fixed10 = std::make_unique<World>(build_scene(bed_scene(n, kBenchDt, 1e-300, 10), "step_bench"));
  return beds.emplace(n, std::move(bed)).first->second;
}

enum class Variant { Converged, Fixed10, ByVelocity };

void run_steps(benchmark::State& st, Variant variant) {
  const int n = static_cast<int>(st.range(0));
  const int threads = static_cast<int>(st.range(1));
  Bed& bed = settled_bed(n);
  World& world = variant == Variant::Fixed10      ? *bed.fixed10
                 : variant == Variant::ByVelocity ? *bed.by_velocity
                                                  : *bed.world;
  world.mutable_state() = bed.rested;
  omp_set_num_threads(threads);
  for (int i = 0; i < 5; ++i) world.step();
  double detect = 0.0, solve = 0.0, sweeps = 0.0, contacts = 0.0, active = 0.0, unconverged = 0.0, solves = 0.0;
  const int detect_k = static_cast<int>(Phase::Detect), solve_k = static_cast<int>(Phase::Solve);
  for (auto _ : st) {
    world.step();
    detect += world.timers().last_step[detect_k];
    solve += world.timers().last_step[solve_k];
    sweeps += world.stats().iterations;
    contacts += static_cast<double>(world.contacts().size());
    active += world.stats().contacts;
    unconverged += world.stats().converged ? 0.0 : 1.0;
    solves += static_cast<double>(world.stats().iterations) * static_cast<double>(world.contacts().size());
  }
  const double k = static_cast<double>(st.iterations());
  st.counters["N"] = n;
  st.counters["threads"] = threads;
  st.counters["detect_ms"] = 1e3 * detect / k;
  st.counters["solve_ms"] = 1e3 * solve / k;
  st.counters["sweeps"] = sweeps / k;
  st.counters["contacts"] = contacts / k;          // contact points given to the solver
  st.counters["active"] = active / k;              // ... with lambda_n > 0
  st.counters["unconverged"] = unconverged / k;    // fraction of steps at max_iterations
  st.counters["time_per_body"] =
      benchmark::Counter(static_cast<double>(n) * k, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  st.counters["ns_per_solve"] = 1e9 * solve / solves;  // solve phase per local contact solve
  st.counters["KE_ratio"] = kinetic_energy(world.scene(), world.state()) / bed.info.peak;
}

// Converged to tolerance 1e-4 (at most 1000 sweeps).
void BM_Step(benchmark::State& st) { run_steps(st, Variant::Converged); }
// Exactly 10 sweeps per step, as a fixed-iteration engine would do (not converged).
void BM_Step10(benchmark::State& st) { run_steps(st, Variant::Fixed10); }
// Converged to 1e-4 in the kinetic-energy norm of the velocity change (solver.criterion
// "velocity", docs/method.md): the same bed, blind to load moving between redundant contacts.
void BM_StepV(benchmark::State& st) { run_steps(st, Variant::ByVelocity); }

void Args(benchmark::internal::Benchmark* b) {
  for (int n : {250, 500, 1000, 2000, 4000, 8000})
    for (int threads : {1, 2}) b->Args({n, threads});
}

BENCHMARK(BM_Step)
    ->Name("Step")
    ->Apply(Args)
    ->ArgNames({"N", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);
BENCHMARK(BM_StepV)
    ->Name("StepV")
    ->Apply(Args)
    ->ArgNames({"N", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);
BENCHMARK(BM_Step10)
    ->Name("Step10")
    ->Apply(Args)
    ->ArgNames({"N", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

}  // namespace
