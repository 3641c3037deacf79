#include "ratchet/solver/local_coulomb.hpp"

#include <cmath>

namespace ratchet {

namespace {

// Tolerances of the sliding branch (dimensionless: angles in rad, residuals relative to |u_t|).
constexpr int kNewtonCap = 30;              // Newton steps; 3-6 suffice from the stick direction
constexpr double kNewtonMaxStep = 0.5;      // |tau| per step: atan(0.5) = 27 degrees keeps Newton in its basin
constexpr double kNewtonStepTol = 1e-14;    // a step this small is round-off
constexpr double kNewtonSmallStep = 1e-6;   // below it, a step no smaller than the last one is the rounding floor
constexpr double kSlideResidualFloor = 1e-15;  // |d x u_t| / |u_t| at round-off
constexpr double kAdmissibleResidual = 1e-9;   // u_t parallel to d within 1e-9 rad: W's round-off with a wide margin
constexpr double kDerivativeFloor = 1e-300;   // |g'| (velocity) not above it: 0, denormal or NaN, no usable Newton step
constexpr int kFixedPointSteps = 2;  // one step converges where the fixed point is exact, the second confirms it
constexpr int kBisectionSteps = 60;  // 2 pi / 256 halved 60 times: 2e-20 rad, machine precision of any angle above 1e-4

// Sliding solution for a given friction direction d (unit, in the tangent plane):
// lambda_t = mu lambda_n d and u_n = 0 fix lambda_n; returns the tangential velocity.
struct SlideTrial {
  double lambda_n = 0.0;
  Eigen::Vector2d u_t = Eigen::Vector2d::Zero();
  bool valid = false;
};

SlideTrial slide_trial(const Mat3& W, const Vec3& w, double mu, const Eigen::Vector2d& d) {
  const Eigen::Vector2d W_nt(W(0, 1), W(0, 2));
  const double denom = W(0, 0) + mu * W_nt.dot(d);
  if (!(denom > 0.0)) return {0.0, Eigen::Vector2d::Zero(), false};
  const double ln = -w[0] / denom;
  const Eigen::Vector2d W_tn(W(1, 0), W(2, 0));
  Eigen::Matrix2d W_tt;
  W_tt << W(1, 1), W(1, 2), W(2, 1), W(2, 2);
  const Eigen::Vector2d u_t = Eigen::Vector2d(w[1], w[2]) + W_tn * ln + W_tt * (mu * ln * d);
  return {ln, u_t, true};
}

// Residual of the sliding condition "u_t antiparallel to d": the 2D cross product,
// normalised; zero at a solution.
double slide_residual(const SlideTrial& s, const Eigen::Vector2d& d) {
  const double norm = s.u_t.norm();
  if (norm == 0.0) return 0.0;
  return (d.x() * s.u_t.y() - d.y() * s.u_t.x()) / norm;
}

// Newton on the angle of d from the start direction, on g(d) = d x u_t(d) (zero where
// u_t is parallel to d), with the derivative along dp = d rotated by 90 degrees in closed
// form: lambda_n = -w_n / (W_nn + mu W_nt.d), u_t = w_t + W_tn lambda_n + mu W_tt lambda_n d.
// The step tau = -g / g' rotates d to (d + tau dp) / |d + tau dp|, i.e. by atan(tau)
// instead of tau: the same first-order step, so convergence stays quadratic, and no
// sin/cos is evaluated (they took a third of the local solve). Converges in a few steps
// where the fixed point is not contractive (u_t small against the coupling mu W_tt near
// the stick boundary). One lane is one problem and where its iteration stands.
struct NewtonLane {
  const Mat3* W = nullptr;
  const Vec3* w = nullptr;
  double mu = 0.0;
  Eigen::Vector2d W_nt, W_tn, da;
  Eigen::Matrix2d W_tt;
  double last_step = HUGE_VAL;
};

NewtonLane newton_lane(const Mat3& W, const Vec3& w, double mu, const Eigen::Vector2d& start) {
  NewtonLane L;
  L.W = &W;
  L.w = &w;
  L.mu = mu;
  L.W_nt = Eigen::Vector2d(W(0, 1), W(0, 2));
  L.W_tn = Eigen::Vector2d(W(1, 0), W(2, 0));
  L.W_tt << W(1, 1), W(1, 2), W(2, 1), W(2, 2);
  L.da = start;
  return L;
}

// One Newton step of the lane; false when its iteration stops there.
[[gnu::always_inline]] inline bool newton_step(NewtonLane& L) {
  const Mat3& W = *L.W;
  const Vec3& w = *L.w;
  const double mu = L.mu;
  const Eigen::Vector2d& W_nt = L.W_nt;
  const Eigen::Vector2d& W_tn = L.W_tn;
  const Eigen::Matrix2d& W_tt = L.W_tt;
  Eigen::Vector2d& da = L.da;
  const Eigen::Vector2d dp(-da.y(), da.x());
  const double denom = W(0, 0) + mu * W_nt.dot(da);
  if (!(denom > 0.0)) return false;
  const double ln = -w[0] / denom;
  const double ln_p = w[0] * mu * W_nt.dot(dp) / (denom * denom);
  const Eigen::Vector2d ut = Eigen::Vector2d(w[1], w[2]) + W_tn * ln + W_tt * (mu * ln * da);
  const Eigen::Vector2d ut_p = W_tn * ln_p + W_tt * (mu * (ln_p * da + ln * dp));
  const double g = da.x() * ut.y() - da.y() * ut.x();
  const double un = ut.norm();
  if (!(un > 0.0) || std::abs(g) < kSlideResidualFloor * un) return false;
  const double g_p = dp.x() * ut.y() + da.x() * ut_p.y() - dp.y() * ut.x() - da.y() * ut_p.x();
  if (!(std::abs(g_p) > kDerivativeFloor)) return false;
  double tau = -g / g_p;
  if (std::abs(tau) > kNewtonMaxStep) tau = tau > 0.0 ? kNewtonMaxStep : -kNewtonMaxStep;  // stay in the basin
  da = (da + tau * dp).normalized();
  // Converged to round-off: a step below kNewtonStepTol rad, or a small step no smaller
  // than the one before (quadratic convergence has reached the rounding floor of g).
  // The test |g| < 1e-15 |u_t| alone is out of reach near the stick boundary, where u_t
  // is small against the terms it is summed from: 80 % of the slides of a settled bed
  // ran to the 30-step cap, a third of the solve phase.
  const double step = std::abs(tau);
  if (step < kNewtonStepTol || (step < kNewtonSmallStep && step >= L.last_step)) return false;
  L.last_step = step;
  return true;
}

// True, with the direction in da, when the lane ended at an admissible sliding direction
// (lambda_n >= 0, u_t against d); t is then the slide trial of da. cut: the lane was
// stopped by a step budget (an inexact slide, slide_from_hint), not by its convergence:
// u_t need not be parallel to d yet, only against it.
bool newton_admissible(const NewtonLane& L, Eigen::Vector2d& da, SlideTrial& t, bool cut = false) {
  da = L.da;
  t = slide_trial(*L.W, *L.w, L.mu, da);
  return t.valid && t.lambda_n >= 0.0 && t.u_t.dot(da) < 0.0 && t.u_t.norm() > 0.0 &&
         (cut || std::abs(slide_residual(t, da)) < kAdmissibleResidual);
}

// The steps a lane may take: all it needs (kNewtonCap) or the inexact slide's budget.
int step_cap(int max_steps) { return max_steps > 0 && max_steps < kNewtonCap ? max_steps : kNewtonCap; }

bool newton_slide(const Mat3& W, const Vec3& w, double mu, const Eigen::Vector2d& start, Eigen::Vector2d& da,
                  SlideTrial& t, int max_steps = 0) {
  NewtonLane L = newton_lane(W, w, mu, start);
  const int cap = step_cap(max_steps);
  bool cut = true;
  for (int it = 0; it < cap; ++it)
    if (!newton_step(L)) { cut = false; break; }
  return newton_admissible(L, da, t, cut && cap < kNewtonCap);
}

Vec3 slide_impulse(const SlideTrial& f, double mu, const Eigen::Vector2d& d) {
  return Vec3(f.lambda_n, mu * f.lambda_n * d.x(), mu * f.lambda_n * d.y());
}

}  // namespace

LocalSolution solve_local_coulomb(const Mat3& W, const Vec3& w, double mu) {
  return solve_local_coulomb(W, W.inverse(), w, mu);
}

bool detail::slide_from_hint(const Mat3& W, const Vec3& w, double mu, const Eigen::Vector2d& hint, Vec3& lambda,
                             int max_steps) {
  Eigen::Vector2d da;
  SlideTrial f;
  if (!newton_slide(W, w, mu, hint, da, f, max_steps)) return false;
  lambda = slide_impulse(f, mu, da);
  return true;
}

namespace {

// N lanes, N known when compiled so that the lanes' loops unroll.
template <int N>
void slide_lanes(const Mat3* const W[], const Vec3* const w[], const double mu[], const Eigen::Vector2d* const hint[],
                 Vec3* lambda[], bool found[], const int max_steps[]) {
  NewtonLane L[N];
  bool active[N];
  int cap[N];
  for (int k = 0; k < N; ++k) {
    L[k] = newton_lane(*W[k], *w[k], mu[k], *hint[k]);
    active[k] = true;
    cap[k] = step_cap(max_steps[k]);
  }
  // Each lane takes exactly the steps it would alone (at most its cap).
  for (int it = 0; it < kNewtonCap; ++it) {
    bool any = false;
    for (int k = 0; k < N; ++k) {
      if (it >= cap[k]) continue;  // its budget spent: it stays as its last step left it
      if (active[k]) active[k] = newton_step(L[k]);
      any = any || (active[k] && it + 1 < cap[k]);
    }
    if (!any) break;
  }
  for (int k = 0; k < N; ++k) {
    Eigen::Vector2d da;
    SlideTrial f;
    found[k] = newton_admissible(L[k], da, f, active[k] && cap[k] < kNewtonCap);
    if (found[k]) *lambda[k] = slide_impulse(f, mu[k], da);
  }
}

}  // namespace

void detail::slide_from_hints(int n, const Mat3* const W[], const Vec3* const w[], const double mu[],
                              const Eigen::Vector2d* const hint[], Vec3* lambda[], bool found[],
                              const int max_steps[]) {
  static constexpr int kExact[kSlideLanes] = {};
  if (max_steps == nullptr) max_steps = kExact;
  switch (n) {
    case 2: slide_lanes<2>(W, w, mu, hint, lambda, found, max_steps); break;
    case 3: slide_lanes<3>(W, w, mu, hint, lambda, found, max_steps); break;
    case 4: slide_lanes<4>(W, w, mu, hint, lambda, found, max_steps); break;
    default:
      for (int k = 0; k < n; ++k)
        found[k] = slide_from_hint(*W[k], *w[k], mu[k], *hint[k], *lambda[k], max_steps[k]);
  }
}

LocalSolution detail::solve_local_slide(const Mat3& W, const Vec3& w, double mu, const Vec3& stick, double lt,
                                        const Eigen::Vector2d* hint, int max_steps) {
  // From the direction the contact slid in at its last solve: in a sweep that is nearly
  // converged Newton lands on the same admissible root in one or two steps. Any other
  // outcome goes the cold way, unchanged.
  LocalSolution sol;
  sol.status = LocalStatus::Slide;
  if (hint != nullptr && slide_from_hint(W, w, mu, *hint, sol.lambda, max_steps)) return sol;
  return slide_cold(W, w, mu, stick, lt);
}

LocalSolution detail::slide_cold(const Mat3& W, const Vec3& w, double mu, const Vec3& stick, double lt) {
  LocalSolution sol;
  sol.status = LocalStatus::Slide;
  Eigen::Vector2d d0;
  if (slide_fixed_point(W, w, mu, stick, lt, d0, sol.lambda)) return sol;
  if (slide_from_hint(W, w, mu, d0, sol.lambda)) return sol;
  sol.lambda = slide_scan(W, w, mu, stick, d0);
  return sol;
}

bool detail::slide_fixed_point(const Mat3& W, const Vec3& w, double mu, const Vec3& stick, double lt,
                               Eigen::Vector2d& d0, Vec3& lambda) {
  // Slide: find the direction d with u_t(d) = -k d, k > 0. Fixed point
  // d <- -u_t(d)/|u_t(d)| from the stick trial direction; it converges in one step when
  // W_tt is isotropic and W_nt = 0 (a sphere on a plane). Otherwise it is slow to reach
  // 1e-13 (28 of 121,000 slides of a settled polyhedron bed did within 8 steps), so
  // after two steps Newton takes over.
  Eigen::Vector2d d = lt > 0.0 ? Eigen::Vector2d(stick[1] / lt, stick[2] / lt)
                               : Eigen::Vector2d(-w[1], -w[2]).normalized();
  if (!d.allFinite()) d = Eigen::Vector2d(1.0, 0.0);
  d0 = d;  // the stick trial direction
  constexpr double kDirTol = 1e-13;  // direction converged to near round-off
  for (int it = 0; it < kFixedPointSteps; ++it) {
    const SlideTrial s = slide_trial(W, w, mu, d);
    if (!s.valid) break;
    const double un = s.u_t.norm();
    if (un == 0.0) break;
    const Eigen::Vector2d d_next = -s.u_t / un;
    if ((d_next - d).norm() < kDirTol && s.lambda_n >= 0.0) {
      const SlideTrial f = slide_trial(W, w, mu, d_next);
      lambda = Vec3(f.lambda_n, mu * f.lambda_n * d_next.x(), mu * f.lambda_n * d_next.y());
      return true;
    }
    d = d_next;
  }
  return false;
}

Vec3 detail::slide_scan(const Mat3& W, const Vec3& w, double mu, const Vec3& stick, const Eigen::Vector2d& d0) {
  // Fallback for strongly coupled W: scan the angle of d for sign changes of the
  // residual, bisect each to machine precision, and keep the admissible roots
  // (lambda_n >= 0, u_t . d < 0). Several may exist when mu is large (the local problem
  // is not unique then); take the one nearest the stick trial direction, so the choice
  // is deterministic and continuous with the stick branch.
  auto dir = [](double a) { return Eigen::Vector2d(std::cos(a), std::sin(a)); };
  auto residual_at = [&](double a) {
    const Eigen::Vector2d da = dir(a);
    return slide_residual(slide_trial(W, w, mu, da), da);
  };
  constexpr int kSamples = 256;
  bool found = false;
  double best_angle = 0.0, best_score = -HUGE_VAL;
  double a0 = 0.0, r0 = residual_at(a0);
  for (int k = 1; k <= kSamples; ++k) {
    const double a1 = 2.0 * M_PI * k / kSamples;
    const double r1 = residual_at(a1);
    if (r0 == 0.0 || (r0 < 0.0) != (r1 < 0.0)) {
      double lo = a0, hi = a1, rlo = r0;
      for (int b = 0; b < kBisectionSteps && rlo != 0.0; ++b) {
        const double mid = 0.5 * (lo + hi);
        const double rm = residual_at(mid);
        if ((rm < 0.0) == (rlo < 0.0)) { lo = mid; rlo = rm; } else { hi = mid; }
      }
      const Eigen::Vector2d dr = dir(lo);
      const SlideTrial t = slide_trial(W, w, mu, dr);
      const double un = t.u_t.norm();
      const bool admissible = t.valid && t.lambda_n >= 0.0 && t.u_t.dot(dr) < 0.0 &&
                              std::abs(slide_residual(t, dr)) < kAdmissibleResidual && un > 0.0;
      if (admissible && dr.dot(d0) > best_score) { best_score = dr.dot(d0); best_angle = lo; found = true; }
    }
    a0 = a1;
    r0 = r1;
  }
  if (found) {
    const Eigen::Vector2d db = dir(best_angle);
    const SlideTrial f = slide_trial(W, w, mu, db);
    return Vec3(f.lambda_n, mu * f.lambda_n * db.x(), mu * f.lambda_n * db.y());
  }
  // No admissible sliding direction found (not seen in the property test of
  // tests/solver/local_coulomb_test.cpp): project the stick impulse onto the cone.
  return project_onto_cone(stick, mu);
}

}  // namespace ratchet
