#include "ratchet/solver/nsgs.hpp"

#include <algorithm>
#include <cmath>

#include "ratchet/solver/anderson.hpp"
#include "ratchet/solver/local_coulomb.hpp"

namespace ratchet {

namespace {

// A compliant row whose overlap asks for a separation speed above the cap: the rigid
// law with the capped speed (u_n >= cap) is the second law, and the row takes whichever
// solution pushes less. Under load the spring's pushes less and is kept bit for bit;
// an unloaded overlap leaves at the cap (docs/method.md s. 5, "Energy-safe relaxation").
Vec3 weaker_push(const SolverRow& c, const Vec3& w, const Vec3& spring) {
  Vec3 w_cap = w;
  w_cap[0] += c.bias_capped - c.bias;
  const Vec3 capped = solve_local_coulomb(c.W, c.W.inverse(), w_cap, c.mu).lambda;
  return capped[0] < spring[0] ? capped : spring;
}

// One Gauss-Seidel sweep in row order: each contact solved exactly with the others
// frozen, its change applied at once. d2 and l2 accumulate |d lambda|^2 and |lambda|^2.
// Record: also write each row's impulse before and after into x and g (3 per row), for
// the Anderson acceleration, while the row is in cache.
template <bool Record>
[[gnu::always_inline]] inline void sweep(std::vector<SolverRow>& cs, SolverBodies& bodies, bool friction,
                                         bool rotation, double& d2, double& l2, std::int64_t& tangential,
                                         double* x = nullptr, double* g = nullptr) {
  const BodyArrays B = arrays_of(bodies);
  for (SolverRow& c : cs) {
    const Vec3 u = local_velocity(c, B, rotation);
    Vec3 lambda_new;
    if (friction) {
      // w = u - W lambda (velocity without this contact's impulse) + bias on the normal.
      Vec3 w = u - c.W * c.lambda;
      w[0] += c.bias;
      if (c.compliance > 0.0) {  // the local law on u + c lambda: the block W + c I (docs/method.md s. 5)
        Mat3 Wc = c.W;
        Wc.diagonal().array() += c.compliance;
        lambda_new = solve_local_coulomb(Wc, c.W_inv, w, c.mu).lambda;
        if (c.bias_capped != 0.0) lambda_new = weaker_push(c, w, lambda_new);
      } else {
        lambda_new = solve_local_coulomb(c.W, c.W_inv, w, c.mu).lambda;
      }
      ++tangential;
    } else {
      const double w_n = u[0] - c.W(0, 0) * c.lambda[0] + c.bias;
      double l_n = solve_local_normal(c.W(0, 0) + c.compliance, w_n);
      if (c.bias_capped != 0.0) l_n = std::min(l_n, solve_local_normal(c.W(0, 0), w_n - c.bias + c.bias_capped));
      lambda_new = Vec3(l_n, 0.0, 0.0);
    }
    const Vec3 d = lambda_new - c.lambda;
    if (d.squaredNorm() > 0.0) apply_local_impulse(c, d, B, rotation);
    if constexpr (Record) {
      for (int j = 0; j < 3; ++j) { x[j] = c.lambda[j]; g[j] = lambda_new[j]; }
      x += 3;
      g += 3;
    }
    c.lambda = lambda_new;
    d2 += d.squaredNorm();
    l2 += lambda_new.squaredNorm();
  }
}

// The extrapolated impulses into the rows, and the body velocities rebuilt for them as
// they are written: v = v_free + M^-1 H lambda (one pass over the rows).
void write_extrapolated(std::vector<SolverRow>& cs, const AndersonMixer& mixer, SolverBodies& B,
                        const SolverScratch& s, bool rotation) {
  B.v = s.v_free;
  B.w = s.w_free;
  const BodyArrays arrays = arrays_of(B);
  for (std::size_t k = 0; k < cs.size(); ++k) {
    cs[k].lambda = mixer.extrapolated(k, cs[k].mu);
    apply_local_impulse(cs[k], cs[k].lambda, arrays, rotation);
  }
}

}  // namespace

double velocity_change(const SolverBodies& B, const std::vector<Vec3>& v0, const std::vector<Vec3>& w0,
                       bool rotation) {
  double e = 0.0;
  for (std::size_t i = 0; i < B.v.size(); ++i) {
    if (B.mass[i] == 0.0) continue;  // fixed
    e += B.mass[i] * (B.v[i] - v0[i]).squaredNorm();
    if (rotation) {
      const double sc = B.scale[i];
      const Vec3 dw = B.R[i].transpose() * (B.w[i] - w0[i]);
      e += (sc * sc) * dw.dot(B.principal_inertia[i].cwiseProduct(dw));
    }
  }
  return e;
}

// Sweep the contacts, solve each exactly with the others frozen, apply the change at
// once. The residual, by solver.criterion (docs/method.md s. 7):
// - impulse: ||d lambda|| / ||lambda|| over the sweep;
// - velocity: sqrt(dE_sweep / E_contact), dE_sweep the kinetic-energy norm of the
//   sweep's change of the body velocities and E_contact that of the change the contact
//   impulses made to the free velocities: the norm of H^T d lambda in M^-1 (Jean 1999,
//   eq. 40), so impulses that only move load between redundant contacts of a
//   hyperstatic packing (the null space of H^T) do not count. Close to LMGC90's 'Quad'
//   norm.
NsgsResult solve_nsgs(std::vector<SolverRow>& cs, SolverBodies& B, const NsgsSettings& set,
                        SolverScratch& s) {
  NsgsResult out;
  const double tol = set.tolerance;
  const bool friction = set.friction, rotation = set.rotation;
  int it = 0;
  double residual = 0.0;
  const int half = set.max_iterations / 2;
  double normal_half = -1.0;  // sum of the normal impulses after half the allowed sweeps
  std::int64_t tangential = 0;
  AndersonMixer mixer(set.anderson_depth);
  const bool accelerate = set.anderson_depth > 0;
  for (it = 1; it <= set.max_iterations && !cs.empty(); ++it) {
    if (set.by_velocity) { s.v_sweep = B.v; s.w_sweep = B.w; }
    double d2 = 0.0, l2 = 0.0;
    if (accelerate)
      sweep<true>(cs, B, friction, rotation, d2, l2, tangential, mixer.record_buffer(cs.size(), false),
                  mixer.record_buffer(cs.size(), true));
    else
      sweep<false>(cs, B, friction, rotation, d2, l2, tangential);
    if (set.by_velocity) {
      const double de = velocity_change(B, s.v_sweep, s.w_sweep, rotation);
      const double e = velocity_change(B, s.v_free, s.w_free, rotation);
      residual = e > 0.0 ? std::sqrt(de / e) : std::sqrt(de);
    } else {
      residual = l2 > 0.0 ? std::sqrt(d2 / l2) : std::sqrt(d2);
    }
    if (it == half) {
      normal_half = 0.0;
      for (const SolverRow& c : cs) normal_half += c.lambda[0];
    }
    if (residual < tol) break;
    if (accelerate && mixer.plan(cs)) write_extrapolated(cs, mixer, B, s, rotation);
  }
  out.sweeps = cs.empty() ? 0 : std::min(it, set.max_iterations);
  out.converged = cs.empty() || residual < tol;
  double normal_end = 0.0;
  for (const SolverRow& c : cs) normal_end += c.lambda[0];
  // An unconverged step whose normal impulses still grew by half over the second half
  // of its sweeps signals a rigid problem with no solution: there they grow in
  // proportion to the sweep count (World::keep_impulses). A solvable problem that is
  // merely slow has settled its normal impulses long before.
  out.normal_growth = !out.converged && normal_half >= 0.0 && normal_end > 1.5 * normal_half;
  out.residual = residual;
  out.tangential_solves = tangential;
  out.restarts = mixer.restarts();
  return out;
}

}  // namespace ratchet
