#include "ratchet/solver/nsgs.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "ratchet/solver/anderson.hpp"
#include "ratchet/solver/apgd.hpp"
#include "ratchet/solver/local_coulomb.hpp"

namespace ratchet {

namespace {

constexpr double kStallProgress = 0.5;  // a new mark: the residual below half the last mark
// A compliant solve whose plain sweeps stall too is relaxed, halving each time down to
// this: at eps = 0.01 on the paper bed 0.5 and 0.3 converged a cycling step in 226-277
// sweeps where plain sweeps reached the cap of 20 000, and 0.85 did not (docs/method.md,
// Stall guard).
constexpr double kMinRelaxation = 0.25;
constexpr std::int8_t kSpringLaw = 1, kCapLaw = 2;  // SolverRow::law_taken, law_kept
// The rigid law's bound on Anderson's step, in sweeps' worth (AndersonMixer): a
// contraction at rate q asks for about 1 / (1 - q), 100 at q = 0.99; a jam's growth is
// then at most about 100 increments per sweep, which the jam tests still resolve.
constexpr double kRigidStepBound = 100.0;

// A compliant row whose overlap asks for a separation speed above the cap: the rigid
// law with the capped speed (u_n >= cap) is the second law, and the row takes whichever
// solution pushes less. Under load the spring's pushes less and is kept bit for bit;
// an unloaded overlap leaves at the cap (docs/method.md s. 5, "Energy-safe relaxation").
// Once frozen (law_kept), the row keeps the law it last took: the choice between the two
// is not monotone, and a solve whose rows flip between them can cycle without end.
Vec3 weaker_push(SolverRow& c, const Vec3& w, const Vec3& spring) {
  if (c.law_kept == kSpringLaw) return spring;
  Vec3 w_cap = w;
  w_cap[0] += c.bias_capped - c.bias;
  const Vec3 capped = solve_local_coulomb(c.W, c.W.inverse(), w_cap, c.mu).lambda;
  const bool cap = c.law_kept == kCapLaw || (c.law_kept == 0 && capped[0] < spring[0]);
  c.law_taken = cap ? kCapLaw : kSpringLaw;
  return cap ? capped : spring;
}

// A row whose slide is put off to be solved together with others (sweep): its local
// problem as the row left it. Its bodies are no other row's until it is finished.
struct PutOff {
  int row = -1, group = -1;
  Mat3 block;  // W, or W + c I
  Vec3 w, stick;
  double lt = 0.0;
  Eigen::Vector2d hint;  // Newton's start: the last slide's direction, or (cold) the stick direction
  bool cold = false;     // no last slide: the fixed point has run and not converged (detail::slide_cold)
};

// The end of a row's solve: its change applied at once, the impulse before and after
// recorded into x and g (3 each, Record: for the Anderson acceleration, while the row is
// in cache), |d lambda|^2 and |lambda|^2 added to d2 and l2.
// With relax below 1 (a stalled compliant solve), the row moves only that part of the
// way: a convex combination of two impulses in the cone stays in it.
template <bool Record>
[[gnu::always_inline]] inline void finish_row(SolverRow& c, Vec3 lambda_new, const BodyArrays& B, bool rotation,
                                              double relax, double& d2, double& l2, double* x, double* g) {
  if (relax != 1.0) lambda_new = c.lambda + relax * (lambda_new - c.lambda);
  const Vec3 d = lambda_new - c.lambda;
  if (d.squaredNorm() > 0.0) apply_local_impulse(c, d, B, rotation);
  if constexpr (Record) {
    for (int j = 0; j < 3; ++j) { x[j] = c.lambda[j]; g[j] = lambda_new[j]; }
  }
  c.lambda = lambda_new;
  d2 += d.squaredNorm();
  l2 += lambda_new.squaredNorm();
}

// One contact of a Gauss-Seidel sweep: solved exactly with the others frozen, its change
// applied at once. With put_off (a coloured sweep), a slide's Newton iteration is not
// run here (from the last slide's direction, or, without one, from the stick direction
// once the fixed point has not converged): the row's problem goes into *put_off,
// nothing of the row is changed, and the caller finishes it (true).
template <bool Record>
[[gnu::always_inline]] inline bool solve_row(SolverRow& c, const BodyArrays& B, bool friction, bool rotation,
                                             double compliance, double relax, int slide_steps, double& d2,
                                             double& l2, double* x, double* g, PutOff* put_off = nullptr) {
  // A row with no impulse whose gap stays open keeps none, with the bits of the full
  // solve below (w = u - W 0 + b, and every local law gives 0 for w_n >= 0; d and the
  // sums add exact zeros): its normal velocity decides, not the whole local velocity.
  // Not for capped rows, whose second law can push an open row (weaker_push).
  if (friction && c.bias_capped == 0.0 && c.lambda[0] == 0.0 && c.lambda[1] == 0.0 && c.lambda[2] == 0.0 &&
      normal_velocity(c, B, rotation) + c.bias >= 0.0) {
    if constexpr (Record) {
      for (int j = 0; j < 3; ++j) { x[j] = c.lambda[j]; g[j] = 0.0; }
    }
    c.lambda.setZero();
    return false;
  }
  const Vec3 u = local_velocity(c, B, rotation);
  Vec3 lambda_new;
  if (friction) {
    // w = u - W lambda (velocity without this contact's impulse) + bias on the normal.
    Vec3 w = u - c.W * c.lambda;
    w[0] += c.bias;
    Eigen::Vector2d hint;  // the last slide's direction starts Newton (local_coulomb.hpp)
    const Eigen::Vector2d* slid = slide_direction(c.lambda, c.mu, hint) ? &hint : nullptr;
    const double c_row = row_compliance(c, compliance);
    const double shift = c_row > 0.0 ? c_row : 0.0;  // the compliant law: the block W + c I (docs/method.md s. 5)
    LocalSolution sol;
    Vec3 stick;
    double lt = 0.0;
    if (solve_local_before_slide(c.W, c.W_inv, w, c.mu, shift, sol, stick, lt)) {
      lambda_new = sol.lambda;
    } else if (put_off != nullptr && c.bias_capped == 0.0) {
      put_off->block = shift != 0.0 ? shifted_block(c.W, shift) : c.W;
      put_off->cold = slid == nullptr;
      if (!put_off->cold) put_off->hint = hint;
      if (put_off->cold && detail::slide_fixed_point(put_off->block, w, c.mu, stick, lt, put_off->hint, lambda_new)) {
        finish_row<Record>(c, lambda_new, B, rotation, relax, d2, l2, x, g);
        return false;
      }
      put_off->w = w;
      put_off->stick = stick;
      put_off->lt = lt;
      return true;
    } else {
      lambda_new = (shift != 0.0
                        ? detail::solve_local_slide(shifted_block(c.W, shift), w, c.mu, stick, lt, slid, slide_steps)
                        : detail::solve_local_slide(c.W, w, c.mu, stick, lt, slid, slide_steps)).lambda;
    }
    if (c.bias_capped != 0.0) lambda_new = weaker_push(c, w, lambda_new);
  } else {
    const double w_n = u[0] - c.W(0, 0) * c.lambda[0] + c.bias;
    double l_n = solve_local_normal(c.W(0, 0) + row_compliance(c, compliance), w_n);
    if (c.bias_capped != 0.0) {
      const double l_cap = solve_local_normal(c.W(0, 0), w_n - c.bias + c.bias_capped);
      const bool cap = c.law_kept == kCapLaw || (c.law_kept == 0 && l_cap < l_n);
      c.law_taken = cap ? kCapLaw : kSpringLaw;
      l_n = cap ? l_cap : l_n;
    }
    lambda_new = Vec3(l_n, 0.0, 0.0);
  }
  finish_row<Record>(c, lambda_new, B, rotation, relax, d2, l2, x, g);
  return false;
}

// The slides put off in a coloured sweep, up to kSlideLanes held at a time, each of
// another group: when the batch is full they are solved together (their Newton
// iterations interleaved, detail::slide_from_hints, each with the bits it has alone),
// and the held ones are solved before the next row of a held row's group and at the end
// of the thread's share of a colour. Rows of other groups of the colour touch other
// bodies, so solving a row later among them changes no bit; its group's sums still get
// its terms in row order. gs: the per-group sums (|d lambda|^2, |lambda|^2).
template <bool Record>
struct SlideBatch {
  SolverRow* rows;
  const BodyArrays& B;
  bool rotation;
  double compliance;
  double relax;
  int slide_steps;  // solver.slide_newton_steps for a hinted slide (a cold one is solved exactly)
  double* gs;
  double* x;
  double* g;
  PutOff held[detail::kSlideLanes];
  int count = 0;

  [[gnu::always_inline]] void finish(const PutOff& p, const Vec3& lambda) {
    finish_row<Record>(rows[p.row], lambda, B, rotation, relax, gs[2 * p.group], gs[2 * p.group + 1],
                       Record ? x + 3 * p.row : x, Record ? g + 3 * p.row : g);
  }
  // Newton from the hint did not end at an admissible slide: a hinted row goes the cold
  // way, a cold one (whose fixed point and Newton from the stick direction have run) on
  // to the scan.
  Vec3 fallback(const PutOff& p) {
    const double mu = rows[p.row].mu;
    return p.cold ? detail::slide_scan(p.block, p.w, mu, p.stick, p.hint)
                  : detail::slide_cold(p.block, p.w, mu, p.stick, p.lt).lambda;
  }
  void solve_held() {
    if (count == 0) return;
    const Mat3* W[detail::kSlideLanes];
    const Vec3* w[detail::kSlideLanes];
    double mu[detail::kSlideLanes];
    const Eigen::Vector2d* hint[detail::kSlideLanes];
    Vec3 lambda[detail::kSlideLanes];
    Vec3* out[detail::kSlideLanes];
    bool found[detail::kSlideLanes];
    int steps[detail::kSlideLanes];
    for (int k = 0; k < count; ++k) {
      steps[k] = held[k].cold ? 0 : slide_steps;
      W[k] = &held[k].block;
      w[k] = &held[k].w;
      mu[k] = rows[held[k].row].mu;
      hint[k] = &held[k].hint;
      out[k] = &lambda[k];
    }
    detail::slide_from_hints(count, W, w, mu, hint, out, found, steps);
    for (int k = 0; k < count; ++k) finish(held[k], found[k] ? lambda[k] : fallback(held[k]));
    count = 0;
  }
  void row(int k, int grp, bool friction) {
    for (int j = 0; j < count; ++j)
      if (held[j].group == grp) { solve_held(); break; }  // a held row comes first in its group
    PutOff& slot = held[count];
    if (!solve_row<Record>(rows[k], B, friction, rotation, compliance, relax, slide_steps, gs[2 * grp], gs[2 * grp + 1],
                           Record ? x + 3 * k : x, Record ? g + 3 * k : g, &slot))
      return;
    slot.row = k;
    slot.group = grp;
    if (++count == detail::kSlideLanes) solve_held();
  }
};

// Rows ahead whose bodies a coloured sweep asks for (prefetch_bodies): a row's solve is
// a few hundred cycles, more than a line's trip from L3.
constexpr int kBodiesAhead = 2;

// Asks for the lines of row r's bodies that local_velocity and apply_local_impulse will
// read and write: a colour's groups meet the bodies all over the bed, in no order the
// hardware follows. A hint only, no value changes; it pays where the bodies leave L2
// (0.97 of the step on a bed of 8000, 1.01 on the paper bed's 2000: docs/performance.md,
// twenty-seventh installment).
[[gnu::always_inline]] inline void prefetch_bodies(const SolverRow& r, const BodyArrays& B, bool rotation) {
  auto body = [&](int i) {
    __builtin_prefetch(B.v + i, 1);
    __builtin_prefetch(B.inv_mass + i, 0);
    if (rotation) {
      __builtin_prefetch(B.w + i, 1);
      const char* inertia = reinterpret_cast<const char*>(B.inv_inertia + i);
      __builtin_prefetch(inertia, 0);
      __builtin_prefetch(inertia + sizeof(Mat3) - 1, 0);
    }
  };
  body(r.a);
  if (!is_wall(r.b)) body(r.b);
}

// One sweep over the rows in their order, colour by colour (solver/row_colouring.hpp):
// the groups of a colour share no moving body, so threads split them without changing a
// bit. |d lambda|^2 and |lambda|^2 are summed per group and then over the groups in
// order, the same sums for any thread count. Without a colouring, one group of all rows.
template <bool Record>
void sweep(std::vector<SolverRow>& cs, SolverBodies& bodies, const RowColouring* colouring, int parallel_min_rows,
           bool friction, bool rotation, double compliance, double relax, int slide_steps, double& d2, double& l2,
           std::vector<double>& sums, double* x = nullptr, double* g = nullptr) {
  const BodyArrays B = arrays_of(bodies);
  if (colouring == nullptr) {
    for (std::size_t k = 0; k < cs.size(); ++k)
      solve_row<Record>(cs[k], B, friction, rotation, compliance, relax, slide_steps, d2, l2, Record ? x + 3 * k : x,
                        Record ? g + 3 * k : g);
    return;
  }
  const RowColouring& col = *colouring;
  const int ng = col.groups(), nc = col.colours();
  sums.resize(2 * static_cast<std::size_t>(ng));
  SolverRow* rows = cs.data();
  double* gs = sums.data();
  const int* gb = col.group_begin.data();
  const int* cb = col.colour_begin.data();
  const int n = static_cast<int>(cs.size());
#pragma omp parallel if (n > parallel_min_rows)
  {
    SlideBatch<Record> batch{rows, B, rotation, compliance, relax, slide_steps, gs, x, g, {}};
    for (int c = 0; c < nc; ++c) {
#pragma omp for schedule(static) nowait
      for (int grp = cb[c]; grp < cb[c + 1]; ++grp) {
        gs[2 * grp] = 0.0;
        gs[2 * grp + 1] = 0.0;
        for (int k = gb[grp]; k < gb[grp + 1]; ++k) {
          if (k + kBodiesAhead < n) prefetch_bodies(rows[k + kBodiesAhead], B, rotation);
          batch.row(k, grp, friction);
        }
      }
      batch.solve_held();
#pragma omp barrier
    }
  }
  for (int grp = 0; grp < ng; ++grp) {
    d2 += gs[2 * grp];
    l2 += gs[2 * grp + 1];
  }
}

// All three entries +0 (not -0): the bits are all clear.
inline bool positive_zeros(const Vec3& v) {
  std::uint64_t b[3];
  std::memcpy(b, v.data(), sizeof b);
  return (b[0] | b[1] | b[2]) == 0;
}

constexpr int kWriteAhead = 8;  // rows fetched ahead by write_extrapolated

// The extrapolated impulses into the rows, and the body velocities for them: the same
// mix of the velocity history (they are linear in the impulses), corrected by the rows
// whose projection onto the cone changed their impulse.
void write_extrapolated(std::vector<SolverRow>& cs, const AndersonMixer& mixer, SolverBodies& B, bool rotation,
                        const RowColouring* colouring, int parallel_min_rows) {
  mixer.extrapolated_velocities(B.v, B.w);
  const BodyArrays arrays = arrays_of(B);
  SolverRow* rows = cs.data();
  const int n = static_cast<int>(cs.size());
  auto write = [&](int k) {
    // The pass reads a line per row, 448 bytes apart: a stride the hardware does not
    // follow, so the line is fetched ahead (1.2 % of the solve, same bits).
    if (k + kWriteAhead < n) __builtin_prefetch(rows + k + kWriteAhead, 1);
    SolverRow& c = rows[k];
    const Vec3 raw = mixer.unprojected(static_cast<std::size_t>(k));
    if (positive_zeros(raw)) {  // an open row's: its projection is itself, nothing to apply
      c.lambda = raw;
      return;
    }
    c.lambda = project_onto_cone(raw, c.mu);
    if (c.lambda != raw) apply_local_impulse(c, Vec3(c.lambda - raw), arrays, rotation);
  };
  if (colouring == nullptr) {
    for (int k = 0; k < static_cast<int>(cs.size()); ++k) write(k);
    return;
  }
  const int* gb = colouring->group_begin.data();
  const int* cb = colouring->colour_begin.data();
  const int nc = colouring->colours();
#pragma omp parallel if (static_cast<int>(cs.size()) > parallel_min_rows)
  for (int c = 0; c < nc; ++c) {
#pragma omp for schedule(static)
    for (int grp = cb[c]; grp < cb[c + 1]; ++grp)
      for (int k = gb[grp]; k < gb[grp + 1]; ++k) write(k);
  }
}

// The rest of a stalled rigid solve by the gradient method (solver.stall_fallback "apgd",
// solver/apgd.hpp), within what is left of max_iterations. Its residual is Coulomb's
// natural-map residual. A jam (no solution) shows as impulses that keep growing: the
// normal sum grew by half since the switch without converging.
SolveResult finish_by_gradient(std::vector<SolverRow>& cs, SolverBodies& B, const SolveSettings& set,
                               SolverScratch& s, int sweeps, std::int64_t tangential, int restarts) {
  SolveResult out;
  const double normal_switch = normal_impulse_sum(cs);
  const ApgdResult g = solve_apgd(cs, B, set, s, set.max_iterations - sweeps);
  out.sweeps = sweeps + g.iterations;
  out.apgd_iterations = g.iterations;
  out.converged = g.converged;
  out.residual = g.residual;
  out.normal_growth = normal_impulses_grew(g.converged, normal_switch, normal_impulse_sum(cs));
  out.tangential_solves = tangential;
  out.restarts = restarts;
  out.plain_fallback = true;
  return out;
}

}  // namespace


// Sweep the contacts, solve each exactly with the others frozen, apply the change at
// once. The residual, by solver.criterion (docs/method.md s. 7):
// - impulse: ||d lambda|| / ||lambda|| over the sweep;
// - velocity: sqrt(dE_sweep / E_contact), dE_sweep the kinetic-energy norm of the
//   sweep's change of the body velocities and E_contact that of the change the contact
//   impulses made to the free velocities: the norm of H^T d lambda in M^-1 (Jean 1999,
//   eq. 40), so impulses that only move load between redundant contacts of a
//   hyperstatic packing (the null space of H^T) do not count. Close to LMGC90's 'Quad'
//   norm.
SolveResult solve_nsgs(std::vector<SolverRow>& cs, SolverBodies& B, const SolveSettings& set,
                        SolverScratch& s) {
  SolveResult out;
  const double tol = set.tolerance;
  const bool friction = set.friction, rotation = set.rotation;
  int it = 0;
  double residual = 0.0;
  const int half = set.max_iterations / 2;
  double normal_half = -1.0;  // sum of the normal impulses after half the allowed sweeps
  // An accelerated rigid solve's jam test (jam_persisted): the first sweep's normal sum
  // and change, and the last sweep's change.
  const bool persist_test = set.rigid && set.anderson_depth > 0;
  double normal_first = -1.0, change_first = 0.0, change_last = 0.0;
  std::int64_t tangential = 0;
  AndersonMixer mixer(s.anderson, set.anderson_depth, set.parallel_min_rows, set.rigid ? kRigidStepBound : 0.0);
  bool accelerate = set.anderson_depth > 0;
  // Stall guard: the residual must halve within set.stall_sweeps sweeps of the last
  // halving, or the rest of the solve runs plain sweeps, which contract for a
  // frictionless compliant problem (W + c I is positive definite) while a projected
  // extrapolation can cycle near the cones' edges (a 400 bed stopped at the 5000 cap
  // with residual 4e-4). With friction plain sweeps can cycle too: a compliant solve
  // whose plain sweeps do not halve the residual either is relaxed, more each time it
  // stalls again (docs/method.md, Stall guard). The rigid law is left to its jam tests.
  double mark = HUGE_VAL;
  int mark_it = 0;
  double relax = 1.0;
  // The inexact slide's budget (solver.slide_newton_steps); a stalled solve finishes with
  // exact slides, so that its plain sweeps are the exact method's.
  int slide_steps = set.slide_newton_steps;
  int gradient_from = 0;  // the sweep after which solve_apgd took over (0: it did not)
  for (it = 1; it <= set.max_iterations && !cs.empty(); ++it) {
    if (set.by_velocity) { s.v_sweep = B.v; s.w_sweep = B.w; }
    double d2 = 0.0, l2 = 0.0;
    if (accelerate)
      sweep<true>(cs, B, set.colouring, set.parallel_min_rows, friction, rotation, set.compliance, relax,
                  slide_steps, d2, l2, s.group_sums, mixer.record_buffer(cs.size(), false),
                  mixer.record_buffer(cs.size(), true));
    else
      sweep<false>(cs, B, set.colouring, set.parallel_min_rows, friction, rotation, set.compliance, relax,
                   slide_steps, d2, l2, s.group_sums);
    if (friction) tangential += static_cast<std::int64_t>(cs.size());
    if (set.by_velocity) {
      const double de = velocity_change(B, s.v_sweep, s.w_sweep, rotation);
      const double e = velocity_change(B, s.v_free, s.w_free, rotation);
      residual = e > 0.0 ? std::sqrt(de / e) : std::sqrt(de);
    } else {
      residual = l2 > 0.0 ? std::sqrt(d2 / l2) : std::sqrt(d2);
    }
    if (it == half) normal_half = normal_impulse_sum(cs);
    if (persist_test) {
      change_last = std::sqrt(d2);
      if (it == 1) { normal_first = normal_impulse_sum(cs); change_first = change_last; }
    }
    if (residual < tol) break;
    if (residual < kStallProgress * mark) {
      mark = residual;
      mark_it = it;
    } else if (it - mark_it >= set.stall_sweeps && !out.plain_fallback) {
      // Stalled: plain sweeps from here, and every capped row keeps the law it took, so
      // that each row's law is one monotone law and the sweeps contract.
      accelerate = false;
      out.plain_fallback = true;
      slide_steps = 0;
      for (SolverRow& c : cs) c.law_kept = c.law_taken;
      mark_it = it;  // the plain sweeps' own patience
    } else if (it - mark_it >= set.stall_sweeps && set.compliance > 0.0 && relax > kMinRelaxation) {
      relax *= 0.5;  // the plain sweeps cycle (friction): under-relaxed sweeps damp the cycle
      mark_it = it;
    } else if (it - mark_it >= set.stall_sweeps && set.rigid && set.apgd_fallback) {
      gradient_from = it;  // the rigid plain sweeps stall too: the gradient method goes on from here
      break;
    }
    if (accelerate) {
      mixer.record_velocities(B.v, B.w);
      if (mixer.plan(cs)) write_extrapolated(cs, mixer, B, rotation, set.colouring, set.parallel_min_rows);
    }
  }
  out.relaxation = relax;
  if (gradient_from > 0) return finish_by_gradient(cs, B, set, s, gradient_from, tangential, mixer.restarts());
  out.sweeps = cs.empty() ? 0 : std::min(it, set.max_iterations);
  out.converged = cs.empty() || residual < tol;
  const double normal_end = normal_impulse_sum(cs);
  out.normal_growth = normal_impulses_grew(out.converged, normal_half, normal_end);
  out.persistent_growth =
      persist_test && jam_persisted(out.sweeps, change_first, change_last, normal_first, normal_end);
  out.residual = residual;
  out.tangential_solves = tangential;
  out.restarts = mixer.restarts();
  return out;
}

}  // namespace ratchet
