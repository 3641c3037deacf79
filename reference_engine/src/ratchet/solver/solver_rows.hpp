// The interface every global contact solve shares (solver/nsgs.hpp is one): the rows
// (frames, lever-arm operators, Delassus blocks, biases, impulses), the bodies as a solve
// sees them, the two kernels every method is made of (a contact's local velocity, and
// applying a local impulse to its bodies), the scratch kept between sweeps, the
// velocity norm of the velocity criterion and the jam detector. docs/method.md s. 4-7.
#pragma once

#include <cstdint>
#include <vector>

#include "ratchet/core/contact_side.hpp"
#include "ratchet/core/types.hpp"
#include "ratchet/solver/anderson_buffers.hpp"
#include "ratchet/solver/apgd_buffers.hpp"
#include "ratchet/solver/row_colouring.hpp"

namespace ratchet {

// What one local solve of the sweep reads and writes, packed in its own array (hot
// data): the operators are built once per step so that a local solve is a few 3x3
// products, u = F^T (v_a - v_b) + J_a w_a - J_b w_b + u0 and, for an impulse change d,
// v_a += m_a^-1 F d, w_a += I_a^-1 J_a^T d (and minus for B). 448 bytes, seven cache
// lines from a line's start: a bed of 2000 has about 9000 rows (4 MB, beyond L2) and
// every sweep streams them all. The first line holds what the passes that touch a row
// without solving it read (the impulse and its cone for Anderson's extrapolation, the
// biases of an open row), so that they load one line, not two. The compliance is not
// kept per row: c = solver.compliance * W_nn (SolveSettings::compliance).
struct alignas(64) SolverRow {
  int a = 0, b = 0;                // bodies; b may name a wall (core/contact_side.hpp)
  double mu = 0.0;
  Vec3 lambda = Vec3::Zero();      // local impulse (n, t1, t2) on A
  double bias = 0.0;               // b: u_n + b >= 0 is the velocity form of g(t+h) >= 0
  double bias_capped = 0.0;        // compliant rows: -(speed cap) when it binds, else 0 (docs/method.md s. 5)
  // Which of a capped row's two laws its last solve took (1 spring, 2 cap), and, once a
  // stalled solve has frozen it, the one it keeps (0: the weaker push, chosen each time).
  std::int8_t law_taken = 0, law_kept = 0;
  Mat3 F = Mat3::Identity();       // columns n, t1, t2 (world)
  // F^T u_expansion: the local velocity no body velocity explains; with the spring law also
  // -c lambda_kept along t1, t2 (World::warm_start, docs/method.md s. 5).
  Vec3 u0 = Vec3::Zero();
  Mat3 Ja = Mat3::Zero(), Jb = Mat3::Zero();  // rows r x e_k: angular velocity -> local velocity
  Mat3 W = Mat3::Zero();           // local Delassus block W = H^T M^-1 H (only W(0,0) without friction)
  Mat3 W_inv = Mat3::Zero();       // (W + c I)^-1 (the stick solution), with friction only
};
static_assert(sizeof(SolverRow) == 448, "seven cache lines: a new field costs a line per row and sweep");

// The compliance c of a row (docs/method.md s. 5): the local law holds for u + c lambda.
inline double row_compliance(const SolverRow& r, double compliance) { return compliance * r.W(0, 0); }

// The bodies as the solve sees them: velocities it updates, inverse masses and world
// inverse inertias it applies impulses with, and what the velocity criterion's
// kinetic-energy norm needs (mass, principal inertia, scale, rotation).
struct SolverBodies {
  std::vector<Vec3>& v;
  std::vector<Vec3>& w;
  const std::vector<double>& inv_mass;      // zero for fixed bodies
  const std::vector<Mat3>& inv_inertia;     // world frame, zero without rotation
  const std::vector<Mat3>& R;               // body -> world
  const std::vector<double>& mass;          // zero marks a fixed body (skipped by the norm)
  const std::vector<Vec3>& principal_inertia;
  const std::vector<double>& scale;         // thermal scale of each body
};

// Below this many rows a sweep takes tens of microseconds and a parallel region's start
// and barriers (one per colour) cost more than they save; the solve's passes run on one
// thread then (the same bits either way).
constexpr int kParallelMinRows = 2048;

// The arrays a sweep touches, as raw pointers taken once per sweep: through the
// references of SolverBodies every access reloaded the vector's data pointer (+4 % of
// the sweep's instructions, callgrind).
struct BodyArrays {
  Vec3* v;
  Vec3* w;
  const double* inv_mass;
  const Mat3* inv_inertia;
};

inline BodyArrays arrays_of(SolverBodies& B) {
  return BodyArrays{B.v.data(), B.w.data(), B.inv_mass.data(), B.inv_inertia.data()};
}

// Local relative velocity of A with respect to B at the contact, with the expansion
// velocity: u = F^T (v_a - v_b) + J_a w_a - J_b w_b + u0.
[[gnu::always_inline]] inline Vec3 local_velocity(const SolverRow& r, const BodyArrays& B, bool rotation) {
  Vec3 dv = B.v[r.a];
  if (!is_wall(r.b)) dv -= B.v[r.b];
  Vec3 u = r.F.transpose() * dv + r.u0;
  if (rotation) {
    u += r.Ja * B.w[r.a];
    if (!is_wall(r.b)) u -= r.Jb * B.w[r.b];
  }
  return u;
}

// The normal component of local_velocity alone, with the same operations in the same
// order (each product's sum left to right, then + u0, + J_a w_a, - J_b w_b), so the
// same bits (tests/solver/solver_rows_test.cpp): a row with no impulse needs only it to
// see that its gap stays open.
inline double normal_velocity(const SolverRow& r, const BodyArrays& B, bool rotation) {
  Vec3 dv = B.v[r.a];
  if (!is_wall(r.b)) dv -= B.v[r.b];
  double u = r.F(0, 0) * dv[0] + r.F(1, 0) * dv[1] + r.F(2, 0) * dv[2] + r.u0[0];
  if (rotation) {
    const Vec3& wa = B.w[r.a];
    u += r.Ja(0, 0) * wa[0] + r.Ja(0, 1) * wa[1] + r.Ja(0, 2) * wa[2];
    if (!is_wall(r.b)) {
      const Vec3& wb = B.w[r.b];
      u -= r.Jb(0, 0) * wb[0] + r.Jb(0, 1) * wb[1] + r.Jb(0, 2) * wb[2];
    }
  }
  return u;
}

// Applies the local impulse change d (on A, minus on B): v += m^-1 F d,
// w += I^-1 J^T d (J^T d = r x (F d), the angular impulse). Forced inline: GCC keeps
// it out of line otherwise, and the call costs a tenth of the sweep.
[[gnu::always_inline]] inline void apply_local_impulse(const SolverRow& r, const Vec3& d, const BodyArrays& B,
                                                       bool rotation) {
  const Vec3 P = r.F * d;
  B.v[r.a] += B.inv_mass[r.a] * P;
  if (rotation) B.w[r.a] += B.inv_inertia[r.a] * (r.Ja.transpose() * d);
  if (!is_wall(r.b)) {
    B.v[r.b] -= B.inv_mass[r.b] * P;
    if (rotation) B.w[r.b] -= B.inv_inertia[r.b] * (r.Jb.transpose() * d);
  }
}

// What a solve is asked (from the scene's solver section) and what it reports, the same
// for every method (World::solve chooses the method by solver.method).
struct SolveSettings {
  double tolerance = 1e-4;
  int max_iterations = 100;
  bool by_velocity = false;  // solver.criterion: velocity (else impulse)
  bool friction = true;
  bool rotation = true;
  int anderson_depth = 0;    // > 0: Anderson acceleration with this memory (solver/anderson.hpp)
  double compliance = 0.0;   // solver.compliance: each row's c = compliance * W_nn (row_compliance)
  bool rigid = false;        // the rigid law (solver.compliance 0): an accelerated solve also reports persistent_growth
  int parallel_min_rows = kParallelMinRows;
  const RowColouring* colouring = nullptr;  // the rows' colouring (parallel sweep), or null: one thread in row order
  int stall_sweeps = 100;    // the stall guard's patience: sweeps without halving the residual (solve_nsgs)
  bool apgd_fallback = false;  // solver.stall_fallback "apgd": a stalled rigid solve goes on by solve_apgd
  int slide_newton_steps = 0;  // solver.slide_newton_steps: > 0, a hinted slide's Newton budget (inexact); 0 exact
};

struct SolveResult {
  int sweeps = 0;
  double residual = 0.0;
  bool converged = true;
  bool normal_growth = false;          // unconverged, and the normal impulses still grew
  bool persistent_growth = false;      // accelerated rigid solve: the impulses grew while a sweep's change did not fall (a jam)
  std::int64_t tangential_solves = 0;  // local solves with friction in this call
  int restarts = 0;                    // Anderson history restarts
  bool plain_fallback = false;         // the acceleration stalled and plain sweeps finished
  double relaxation = 1.0;             // the last sweeps' relaxation: below 1 when plain sweeps stalled too
  int apgd_iterations = 0;             // gradient steps of the stall fallback (part of sweeps)
};

// What a solve keeps between sweeps: the velocities before the contact impulses (set
// by World::solve before the warm start, once: the velocity criterion's reference and
// the start a jammed step is solved again from), before each sweep, and per-group sums.
struct SolverScratch {
  std::vector<Vec3> v_free, w_free, v_sweep, w_sweep;
  std::vector<double> group_sums;  // per group of the colouring: |d lambda|^2, |lambda|^2 of a sweep
  AndersonBuffers anderson;        // the acceleration's arrays (solver/anderson_buffers.hpp)
  ApgdBuffers apgd;                // the rigid stall fallback's arrays (solver/apgd_buffers.hpp)
};

// sum_i m_i |v_i - v0_i|^2 + (w_i - w0_i)^T I_i (w_i - w0_i): twice the kinetic energy of
// the velocity difference, I = R diag(I_p s^2) R^T.
double velocity_change(const SolverBodies& bodies, const std::vector<Vec3>& v0, const std::vector<Vec3>& w0,
                       bool rotation);
// The same norm of (v - v0, w - w0) for velocities other than the bodies' own.
double velocity_change(const SolverBodies& bodies, const std::vector<Vec3>& v, const std::vector<Vec3>& w,
                       const std::vector<Vec3>& v0, const std::vector<Vec3>& w0, bool rotation);

// The jam detector (World::keep_impulses, World::yield_to_jam): an unconverged solve
// whose normal impulses still grew by half over the second half of its sweeps signals a
// rigid problem with no solution, where they grow in proportion to the sweep count; a
// solvable problem that is merely slow has settled its normal impulses long before.
double normal_impulse_sum(const std::vector<SolverRow>& rows);
constexpr double kNormalGrowth = 1.5;  // between 1 (settled sums) and 2 (sums in proportion to the sweeps: a jam)
inline bool normal_impulses_grew(bool converged, double sum_at_half, double sum_at_end) {
  return !converged && sum_at_half >= 0.0 && sum_at_end > kNormalGrowth * sum_at_half;
}

// The jam detector of an accelerated solve. Anderson extrapolates a jam's growth: the
// impulses become huge and their relative change falls below the tolerance, so the
// test above never sees it. But the absolute change of a sweep, |G(x) - x|, is the jam's
// constant increment however far x was extrapolated, while a solvable problem's falls
// (by about 0.7 per sweep in a flowing bed; from a cold start by far more than the
// impulses grow). So: the normal impulses grew by half or more since the first sweep,
// and the last sweep changed them by at least a tenth as much as the first did.
constexpr double kPersistentChange = 0.1;  // last sweep's |d lambda| over the first's: 0.4-2 in a jam (JammedSphere), ~1e-4 x the growth after a cold start
inline bool jam_persisted(int sweeps, double first_change, double last_change, double sum_after_first,
                          double sum_at_end) {
  return sweeps >= 3 && sum_after_first >= 0.0 && sum_at_end > kNormalGrowth * sum_after_first &&
         last_change >= kPersistentChange * first_change;
}

}  // namespace ratchet
