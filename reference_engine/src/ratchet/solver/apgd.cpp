#include "ratchet/solver/apgd.hpp"

#include <algorithm>
#include <cmath>

#include "ratchet/solver/fixed_order_passes.hpp"
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

// coulomb_residual, and with `shifts` de Saxcé's shift mu |u_t| of each row at the same
// velocities (the next convex problem's), from the same pass over the rows.
double residual_and_shifts(const std::vector<SolverRow>& rows, SolverBodies& bodies, bool rotation,
                           std::vector<double>* shifts, const FixedOrderPasses& pass) {
  const BodyArrays A = arrays_of(bodies);
  const auto s = pass.sum<2>(static_cast<int>(rows.size()), [&](int k, std::array<double, 2>& acc) {
    const SolverRow& r = rows[static_cast<std::size_t>(k)];
    Vec3 u = local_velocity(r, A, rotation);
    const double shift = r.mu * std::sqrt(u[1] * u[1] + u[2] * u[2]);
    if (shifts != nullptr) (*shifts)[static_cast<std::size_t>(k)] = shift;
    u[0] += r.bias + shift;
    acc[0] += (r.lambda - nearest_in_cone(r.lambda - rho(r) * u, r.mu)).squaredNorm();
    acc[1] += r.lambda.squaredNorm();
  });
  return s[1] > 0.0 ? std::sqrt(s[0] / s[1]) : std::sqrt(s[0]);
}

// The convex problem of de Saxcé's fixed point with the shifts s fixed: minimise
// f(x) = 1/2 x^T W x + x^T (q + s n) over the cones, W = H M^-1 H^T, q the rows' local
// velocities at the free velocities (bias on the normal). Matrix-free: the gradient is
// the rows' local velocity at the bodies' velocities of x, and the step test needs only
// d^T W d, the kinetic-energy norm of the velocity change the impulses d make. Every
// pass may be split among threads with the same bits (FixedOrderPasses; `move` by the
// rows' colours, as the coloured sweep).
struct Problem {
  std::vector<SolverRow>& rows;
  SolverBodies& B;
  const SolveSettings& set;
  ApgdBuffers& buf;
  FixedOrderPasses pass;

  int n() const { return static_cast<int>(rows.size()); }
  int bodies() const { return static_cast<int>(B.v.size()); }

  // The gradient W x + q + s n at the velocities (v, w) of x: the local velocities.
  void gradient(std::vector<Vec3>& v, std::vector<Vec3>& w, std::vector<Vec3>& g) const {
    const BodyArrays A = arrays(v, w, B);
    pass.for_each(n(), [&](int k) {
      const std::size_t i = static_cast<std::size_t>(k);
      g[i] = local_velocity(rows[i], A, set.rotation);
      g[i][0] += rows[i].bias + buf.s[i];
    });
  }

  // (v, w) += M^-1 H^T (to - from): the velocities of `to` from those of `from`. The
  // rows are in the order of their colours (World's contacts; a single group without
  // one), so each body gets its changes in row order however the colours are split.
  void move(const std::vector<Vec3>& from, const std::vector<Vec3>& to, std::vector<Vec3>& v,
            std::vector<Vec3>& w) const {
    const BodyArrays A = arrays(v, w, B);
    auto apply = [&](int k) {
      const std::size_t i = static_cast<std::size_t>(k);
      const Vec3 d = to[i] - from[i];
      if (d.squaredNorm() > 0.0) apply_local_impulse(rows[i], d, A, set.rotation);
    };
    if (!pass.parallel || set.colouring == nullptr) {
      for (int k = 0; k < n(); ++k) apply(k);
      return;
    }
    const int* gb = set.colouring->group_begin.data();
    const int* cb = set.colouring->colour_begin.data();
    const int nc = set.colouring->colours();
#pragma omp parallel
    for (int c = 0; c < nc; ++c) {
#pragma omp for schedule(static)
      for (int grp = cb[c]; grp < cb[c + 1]; ++grp)
        for (int k = gb[grp]; k < gb[grp + 1]; ++k) apply(k);
    }
  }

  // d^T W d of the impulse change that took the velocities from (v0, w0) to (v, w): the
  // norm of velocity_change (solver_rows.hpp), summed in the fixed order.
  double kinetic_norm(const std::vector<Vec3>& v, const std::vector<Vec3>& w, const std::vector<Vec3>& v0,
                      const std::vector<Vec3>& w0) const {
    return pass.sum<1>(bodies(), [&](int k, std::array<double, 1>& acc) {
      const std::size_t i = static_cast<std::size_t>(k);
      if (B.mass[i] == 0.0) return;  // fixed
      acc[0] += B.mass[i] * (v[i] - v0[i]).squaredNorm();
      if (set.rotation) {
        const double sc = B.scale[i];
        const Vec3 dw = B.R[i].transpose() * (w[i] - w0[i]);
        acc[0] += (sc * sc) * dw.dot(B.principal_inertia[i].cwiseProduct(dw));
      }
    })[0];
  }

  // The convex problem's own natural-map residual at x (gradient g at x), relative.
  double convex_residual(const std::vector<Vec3>& x, const std::vector<Vec3>& g) const {
    const auto s = pass.sum<2>(n(), [&](int k, std::array<double, 2>& acc) {
      const std::size_t i = static_cast<std::size_t>(k);
      acc[0] += (x[i] - nearest_in_cone(x[i] - rho(rows[i]) * g[i], rows[i].mu)).squaredNorm();
      acc[1] += x[i].squaredNorm();
    });
    return s[1] > 0.0 ? std::sqrt(s[0] / s[1]) : std::sqrt(s[0]);
  }
};

}  // namespace

double coulomb_residual(const std::vector<SolverRow>& rows, SolverBodies& bodies, bool rotation) {
  std::vector<double> partial;
  return residual_and_shifts(rows, bodies, rotation, nullptr, FixedOrderPasses{false, &partial});
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
  const FixedOrderPasses pass{static_cast<int>(n) > set.parallel_min_rows, &buf.partial};
  Problem P{rows, B, set, buf, pass};
  std::vector<Vec3>& x = buf.x;  // the current iterate (the rows' impulses, whose velocities the bodies hold)
  x.resize(n);
  for (std::size_t k = 0; k < n; ++k) x[k] = rows[k].lambda;
  const int nr = static_cast<int>(n), nb = static_cast<int>(B.v.size());
  double L = 1.0;  // Lipschitz estimate of the scaled gradient (diag(rho) W has 1 on its normal diagonal)
  int it = 0;
  // The residual at the current iterate, and de Saxcé's shifts there for the next problem.
  double residual = residual_and_shifts(rows, B, set.rotation, &buf.s, pass);
  while (it < max_iterations && residual >= set.tolerance) {
    const double inner_tol = std::max(kInnerFraction * set.tolerance, kInnerFraction * residual);
    // Accelerated projected gradient (Mazhar et al. 2015, Alg. 1, in the metric diag(rho)).
    buf.y = x;
    buf.prev = x;
    buf.vy = B.v;
    buf.wy = B.w;
    buf.vn.resize(B.v.size());
    buf.wn.resize(B.w.size());
    double theta = 1.0;
    for (int inner = 0; it < max_iterations; ++inner) {
      P.gradient(buf.vy, buf.wy, buf.g);
      for (;;) {  // backtracking on the quadratic upper bound
        const double t = 1.0 / L;
        const double d2 = pass.sum<1>(nr, [&](int k, std::array<double, 1>& acc) {
          const std::size_t i = static_cast<std::size_t>(k);
          const double rk = rho(rows[i]);
          buf.next[i] = nearest_in_cone(buf.y[i] - (t * rk) * buf.g[i], rows[i].mu);
          const Vec3 d = buf.next[i] - buf.y[i];
          acc[0] += d.squaredNorm() / rk;
        })[0];
        pass.for_each(nb, [&](int i) {
          buf.vn[static_cast<std::size_t>(i)] = buf.vy[static_cast<std::size_t>(i)];
          buf.wn[static_cast<std::size_t>(i)] = buf.wy[static_cast<std::size_t>(i)];
        });
        P.move(buf.y, buf.next, buf.vn, buf.wn);
        ++it;
        // f(next) <= f(y) + g.d + (L/2)|d|^2 with f quadratic is 1/2 d^T W d <= (L/2)|d|^2 in
        // the metric diag(rho) (Beck & Teboulle 2009, s. 3); d^T W d is the kinetic-energy
        // norm of the velocity change d makes. The relative slack 1e-12 is far above the
        // rounding of these sums over thousands of rows (about 1e-16 per term) and far below
        // a real violation, which doubles L.
        const double dWd = P.kinetic_norm(buf.vn, buf.wn, buf.vy, buf.wy);
        if (dWd <= L * d2 * (1.0 + 1e-12) || it >= max_iterations) break;
        L *= 2.0;
      }
      // Momentum, restarted when the step goes uphill (O'Donoghue & Candès 2015).
      const double uphill = pass.sum<1>(nr, [&](int k, std::array<double, 1>& acc) {
        const std::size_t i = static_cast<std::size_t>(k);
        acc[0] += buf.g[i].dot(buf.next[i] - x[i]);
      })[0];
      const double theta_next = 0.5 * (-theta * theta + theta * std::sqrt(theta * theta + 4.0));
      double beta = theta * (1.0 - theta) / (theta * theta + theta_next);
      theta = theta_next;
      if (uphill > 0.0) {
        beta = 0.0;
        theta = 1.0;
      }
      // prev: the last iterate; x: the new one (next is written whole before it is read again).
      buf.prev.swap(x);
      x.swap(buf.next);
      pass.for_each(nr, [&](int k) {
        const std::size_t i = static_cast<std::size_t>(k);
        buf.y[i] = x[i] + beta * (x[i] - buf.prev[i]);
      });
      pass.for_each(nb, [&](int k) {  // the bodies take the new iterate's velocities; y's extrapolated alike
        const std::size_t i = static_cast<std::size_t>(k);
        const Vec3 v_last = B.v[i], w_last = B.w[i];
        B.v[i] = buf.vn[i];
        B.w[i] = buf.wn[i];
        buf.vy[i] = B.v[i] + beta * (B.v[i] - v_last);
        buf.wy[i] = B.w[i] + beta * (B.w[i] - w_last);
      });
      L *= kShrink;
      if ((inner + 1) % kInnerCheckEvery == 0) {
        P.gradient(B.v, B.w, buf.g);
        if (P.convex_residual(x, buf.g) < inner_tol) break;
      }
    }
    pass.for_each(nr, [&](int k) { rows[static_cast<std::size_t>(k)].lambda = x[static_cast<std::size_t>(k)]; });
    residual = residual_and_shifts(rows, B, set.rotation, &buf.s, pass);
  }
  out.iterations = it;
  out.residual = residual;
  out.converged = residual < set.tolerance;
  return out;
}

}  // namespace ratchet
