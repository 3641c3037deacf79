#include "ratchet/solver/apgd.hpp"

#include <algorithm>
#include <cmath>

#include "ratchet/solver/local_coulomb.hpp"

namespace ratchet {

namespace {

// Each convex problem is solved to this fraction of the outer residual (and at least to
// this fraction of the tolerance). Compared on the same problems (each solve of a rigid
// paper bed squeezed by its container solved both ways, the run going on from one):
// 0.3, 0.5, 0.7, 0.8, 0.9 and 10 (one check) took 1.92, 1, 0.78, 0.81, 0.78 and 1.64 times
// the gradient steps of 0.5 (docs/performance.md, "The squeezed rigid bed").
constexpr double kInnerFraction = 0.7;
constexpr int kInnerCheckEvery = 5;  // inner residual every this many steps: it costs a pass over the rows
constexpr double kShrink = 0.9;      // the Lipschitz estimate shrinks each step (Mazhar et al. 2015, Alg. 1)

BodyArrays arrays(std::vector<Vec3>& v, std::vector<Vec3>& w, const SolverBodies& B) {
  return BodyArrays{v.data(), w.data(), B.inv_mass.data(), B.inv_inertia.data()};
}

inline double rho(const SolverRow& r) { return 1.0 / r.W(0, 0); }  // the row's step scale (Jacobi)

// The Euclidean projection onto the cone |x_t| <= mu x_n (not project_onto_cone's radial
// clip): the gradient method and the natural map need the nearest point.
inline Vec3 nearest_in_cone(const Vec3& x, double mu) {
  const double t = std::sqrt(x[1] * x[1] + x[2] * x[2]);
  if (t <= mu * x[0]) return x;                     // inside
  if (mu * t <= -x[0]) return Vec3::Zero();         // in the polar cone
  const double n = (x[0] + mu * t) / (1.0 + mu * mu);  // onto the cone's surface
  const double f = t > 0.0 ? mu * n / t : 0.0;
  return Vec3(n, f * x[1], f * x[2]);
}

// The convex problem of de Saxcé's fixed point with the shifts s fixed: minimise
// f(x) = 1/2 x^T W x + x^T (q + s n) over the cones, W = H M^-1 H^T, q the rows' local
// velocities at the free velocities (bias on the normal). Matrix-free: the gradient is
// the rows' local velocity at the bodies' velocities of x, and the step test needs only
// d^T W d, the kinetic-energy norm of the velocity change the impulses d make.
struct Problem {
  std::vector<SolverRow>& rows;
  SolverBodies& B;
  const SolveSettings& set;
  ApgdBuffers& buf;

  // The gradient W x + q + s n at the velocities (v, w) of x: the local velocities.
  void gradient(std::vector<Vec3>& v, std::vector<Vec3>& w, std::vector<Vec3>& g) const {
    const BodyArrays A = arrays(v, w, B);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      g[k] = local_velocity(rows[k], A, set.rotation);
      g[k][0] += rows[k].bias + buf.s[k];
    }
  }

  // (v, w) += M^-1 H^T (to - from): the velocities of `to` from those of `from`.
  void move(const std::vector<Vec3>& from, const std::vector<Vec3>& to, std::vector<Vec3>& v,
            std::vector<Vec3>& w) const {
    const BodyArrays A = arrays(v, w, B);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const Vec3 d = to[k] - from[k];
      if (d.squaredNorm() > 0.0) apply_local_impulse(rows[k], d, A, set.rotation);
    }
  }
};

// The convex problem's own natural-map residual at x (gradient g at x), relative.
double convex_residual(const std::vector<SolverRow>& rows, const std::vector<Vec3>& x, const std::vector<Vec3>& g) {
  double f2 = 0.0, x2 = 0.0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    f2 += (x[k] - nearest_in_cone(x[k] - rho(rows[k]) * g[k], rows[k].mu)).squaredNorm();
    x2 += x[k].squaredNorm();
  }
  return x2 > 0.0 ? std::sqrt(f2 / x2) : std::sqrt(f2);
}

}  // namespace

namespace {

// coulomb_residual, and with `shifts` de Saxcé's shift mu |u_t| of each row at the same
// velocities (the next convex problem's), from the same pass over the rows.
double residual_and_shifts(const std::vector<SolverRow>& rows, SolverBodies& bodies, bool rotation,
                           std::vector<double>* shifts) {
  const BodyArrays A = arrays_of(bodies);
  double f2 = 0.0, l2 = 0.0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const SolverRow& r = rows[k];
    Vec3 u = local_velocity(r, A, rotation);
    const double shift = r.mu * std::sqrt(u[1] * u[1] + u[2] * u[2]);
    if (shifts != nullptr) (*shifts)[k] = shift;
    u[0] += r.bias + shift;
    f2 += (r.lambda - nearest_in_cone(r.lambda - rho(r) * u, r.mu)).squaredNorm();
    l2 += r.lambda.squaredNorm();
  }
  return l2 > 0.0 ? std::sqrt(f2 / l2) : std::sqrt(f2);
}

}  // namespace

double coulomb_residual(const std::vector<SolverRow>& rows, SolverBodies& bodies, bool rotation) {
  return residual_and_shifts(rows, bodies, rotation, nullptr);
}

ApgdResult solve_apgd(std::vector<SolverRow>& rows, SolverBodies& B, const SolveSettings& set, SolverScratch& scratch,
                      int max_iterations) {
  ApgdResult out;
  const std::size_t n = rows.size();
  if (n == 0) {
    out.converged = true;
    return out;
  }
  ApgdBuffers& buf = scratch.apgd;
  for (auto* a : {&buf.y, &buf.prev, &buf.next, &buf.g}) a->resize(n);
  buf.s.assign(n, 0.0);
  Problem P{rows, B, set, buf};
  std::vector<Vec3>& x = buf.x;  // the current iterate (the rows' impulses, whose velocities the bodies hold)
  x.resize(n);
  for (std::size_t k = 0; k < n; ++k) x[k] = rows[k].lambda;
  double L = 1.0;  // Lipschitz estimate of the scaled gradient (diag(rho) W has 1 on its normal diagonal)
  int it = 0;
  // The residual at the current iterate, and de Saxcé's shifts there for the next problem.
  double residual = residual_and_shifts(rows, B, set.rotation, &buf.s);
  while (it < max_iterations && residual >= set.tolerance) {
    const double inner_tol = std::max(kInnerFraction * set.tolerance, kInnerFraction * residual);
    // Accelerated projected gradient (Mazhar et al. 2015, Alg. 1, in the metric diag(rho)).
    buf.y = x;
    buf.prev = x;
    buf.vy = B.v;
    buf.wy = B.w;
    double theta = 1.0;
    for (int inner = 0; it < max_iterations; ++inner) {
      P.gradient(buf.vy, buf.wy, buf.g);
      for (;;) {  // backtracking on the quadratic upper bound
        const double t = 1.0 / L;
        double d2 = 0.0;
        for (std::size_t k = 0; k < n; ++k) {
          const double rk = rho(rows[k]);
          buf.next[k] = nearest_in_cone(buf.y[k] - (t * rk) * buf.g[k], rows[k].mu);
          const Vec3 d = buf.next[k] - buf.y[k];
          d2 += d.squaredNorm() / rk;
        }
        buf.vn = buf.vy;
        buf.wn = buf.wy;
        P.move(buf.y, buf.next, buf.vn, buf.wn);
        ++it;
        // f(next) <= f(y) + g.d + (L/2)|d|^2 with f quadratic is 1/2 d^T W d <= (L/2)|d|^2 in
        // the metric diag(rho) (Beck & Teboulle 2009, s. 3); d^T W d is the kinetic-energy
        // norm of the velocity change d makes. The relative slack 1e-12 is far above the
        // rounding of these sums over thousands of rows (about 1e-16 per term) and far below
        // a real violation, which doubles L.
        const double dWd = velocity_change(B, buf.vn, buf.wn, buf.vy, buf.wy, set.rotation);
        if (dWd <= L * d2 * (1.0 + 1e-12) || it >= max_iterations) break;
        L *= 2.0;
      }
      // Momentum, restarted when the step goes uphill (O'Donoghue & Candès 2015).
      double uphill = 0.0;
      for (std::size_t k = 0; k < n; ++k) uphill += buf.g[k].dot(buf.next[k] - x[k]);
      const double theta_next = 0.5 * (-theta * theta + theta * std::sqrt(theta * theta + 4.0));
      double beta = theta * (1.0 - theta) / (theta * theta + theta_next);
      theta = theta_next;
      if (uphill > 0.0) {
        beta = 0.0;
        theta = 1.0;
      }
      buf.prev.swap(x);  // prev: the last iterate; x: the new one
      x = buf.next;
      buf.vp = B.v;
      buf.wp = B.w;
      B.v = buf.vn;
      B.w = buf.wn;
      for (std::size_t k = 0; k < n; ++k) buf.y[k] = x[k] + beta * (x[k] - buf.prev[k]);
      for (std::size_t i = 0; i < B.v.size(); ++i) {
        buf.vy[i] = B.v[i] + beta * (B.v[i] - buf.vp[i]);
        buf.wy[i] = B.w[i] + beta * (B.w[i] - buf.wp[i]);
      }
      L *= kShrink;
      if ((inner + 1) % kInnerCheckEvery == 0) {
        P.gradient(B.v, B.w, buf.g);
        if (convex_residual(rows, x, buf.g) < inner_tol) break;
      }
    }
    for (std::size_t k = 0; k < n; ++k) rows[k].lambda = x[k];
    residual = residual_and_shifts(rows, B, set.rotation, &buf.s);
  }
  out.iterations = it;
  out.residual = residual;
  out.converged = residual < set.tolerance;
  return out;
}

}  // namespace ratchet
