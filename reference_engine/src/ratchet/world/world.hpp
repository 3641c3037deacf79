// The world: a scene, its state and the step. Legend (paper symbols):
//   h       time step                  W       local Delassus block
//   u       relative velocity          lambda  contact impulse
//   mu      Coulomb friction           g       signed gap
//   p_gap   gap relaxation             theta   Moreau-Jean parameter
//   alpha_p, alpha_c, s_p, s_c   expansion coefficients and scales of particles and container
#pragma once

#include <string>
#include <vector>

#include "ratchet/contact/collide.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/solver/nsgs.hpp"
#include "ratchet/world/phases.hpp"
#include "ratchet/world/scratch.hpp"
#include "ratchet/world/state.hpp"

namespace ratchet {

// What a step of this scene will do and why (ratchet run --explain, run.json).
struct PlanItem {
  std::string name;
  bool active = true;
  std::string reason;
};

// What the last step did; each step sets every field.
struct StepStats {
  int contacts = 0;
  int iterations = 0;
  double residual = 0.0;
  double wall_force_side = 0.0;    // total normal force on the side walls
  double wall_force_bottom = 0.0;  // normal force on the bottom
  double wall_force_total = 0.0;   // normal force on all walls (side, bottom and plain planes)
  double max_overlap = 0.0;        // the largest overlap (-gap) among the step's contacts as detected, 0 if none
  int manifolds_replayed = 0;      // polyhedron pairs whose kept manifold was replayed (solver.manifold_reuse)
  int manifolds_built = 0;         // ... and those built anew
  bool converged = true;           // the step met the tolerance
  bool normal_growth = false;      // ... and if not, its normal impulses still grew
};

// What the steps of a run add up to (run.json "counters"; kept by checkpoints).
struct RunTotals {
  std::int64_t tangential_solves = 0;  // local solves with friction
  std::int64_t total_iterations = 0;   // Gauss-Seidel sweeps
  std::int64_t unconverged_steps = 0;  // steps that hit solver.max_iterations
  std::int64_t jammed_steps = 0;       // rigid steps solved again without the imposed motion (World::yield_to_jam)
  std::int64_t relaxed_steps = 0;      // compliant steps whose plain sweeps stalled and were relaxed (solve_nsgs)
};

// What a run has done to a world besides its State: the settle stage's end (which moves
// the protocol's start and the run's end), the run's totals and phase timers.
// State plus this is what a checkpoint keeps of a world (run/checkpoint.hpp).
struct WorldProgress {
  bool settling = false;
  double start_time = 0.0, duration = 0.0;  // scene().thermal.start_time, scene().duration
  std::int64_t steps = 0;                   // scene().steps
  RunTotals totals;
  PhaseTimers timers;
};

class World {
 public:
  explicit World(const SceneDef& scene);

  // One Moreau-Jean step of length h, as the named phases of docs/method.md, "The step".
  void step();

  // A scene with a settle section (scene.hpp, SettleDef): the bed has settled at the
  // current state; the thermal protocol and the run's end now count from here.
  // Call once, between steps (run/packing.cpp does).
  void end_settle_stage();
  bool settling() const { return settling_; }

  // A checkpoint's record of the run so far, and its restore into a world fresh from
  // the same scene whose state has been replaced by the checkpoint's.
  WorldProgress progress() const;
  void restore_progress(const WorldProgress& p);

  const SceneDef& scene() const { return scene_; }
  const State& state() const { return state_; }
  // The state to replace or change between steps (a packing, a checkpoint): the next
  // step checks what it keeps per candidate pair anew (world/detect.cpp).
  State& mutable_state() {
    scratch_.slots_aligned = false;
    return state_;
  }
  const StepStats& stats() const { return stats_; }    // the last step
  const RunTotals& totals() const { return totals_; }  // the run so far
  const PhaseTimers& timers() const { return timers_; }
  const std::vector<SolverContact>& contacts() const { return scratch_.contacts; }
  const RowColouring& contact_colouring() const { return scratch_.colouring; }
  std::vector<PlanItem> plan() const;

  // Observables of the current state are functions of (scene, state) in observe/.
  Vec3 wall_point(int wall) const;      // current point of a wall (container scale)
  double body_scale(int i) const;       // thermal scale of body i (scene.hpp, body_scale)

 private:
  void free_velocity();
  void thermal();
  void detect();
  void solve();
  SolveResult solve_contacts(SolverBodies& bodies, const SolveSettings& settings);
  void yield_to_jam(SolverBodies& bodies);
  void integrate();
  void keep_impulses();
  void observe();

  // detect (world/detect.cpp)
  void prepare_bodies();
  void align_pair_slots(const std::vector<BodyPair>& candidates, bool reuse);
  void count_pair_fates();
  void collide_reusing(int k, const CollisionBody& a, const CollisionBody& b);
  void audit_replay(std::size_t slot, const CollisionBody& a, const CollisionBody& b, double moved);
  void reduce_reuse_audit();
  void find_wall_pairs(const std::vector<Vec3>& wall_points);
  void gather_contacts();
  // solve (world/contact_rows.cpp; the global solve is solver/nsgs.hpp)
  void build_rows();
  void warm_start(SolverBodies& bodies);
  void find_kept_impulses();

  SceneDef scene_;
  std::vector<double> body_mass_;    // per body, 0 for fixed bodies (the velocity norm skips them)
  std::vector<Vec3> body_inertia_;   // principal inertia at scale 1
  State state_;
  StepScratch scratch_;
  StepStats stats_;
  RunTotals totals_;
  PhaseTimers timers_;
  bool gravity_on_ = false, thermal_on_ = false, friction_on_ = false, rotation_on_ = false;
  bool settling_ = false;  // a settle section whose stage has not ended yet
};

}  // namespace ratchet
