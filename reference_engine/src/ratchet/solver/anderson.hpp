// Anderson acceleration of the Gauss-Seidel fixed point (Anderson 1965; type II as in
// Walker & Ni 2011, "Anderson acceleration for fixed-point iterations", SIAM J. Numer.
// Anal. 49(4)). A sweep maps impulses x to G(x); with the last m differences of
// f = G(x) - x and of G(x), the next start is
//   x+ = G(x_k) - dG gamma,  gamma = argmin |f_k - dF gamma|,
// projected back onto each contact's Coulomb cone. The fixed point is the one
// Gauss-Seidel converges to, so the local law is solved exactly as before; only the
// route to it is shorter. Residuals are weighted by sqrt(W_nn) per contact, which makes
// them velocities (the energy scale of the problem) instead of raw impulses.
// Restarted (history cleared) whenever |f| grows, as nonsmooth maps can mislead it.
#pragma once

#include <vector>

#include <Eigen/Dense>

#include "ratchet/solver/anderson_buffers.hpp"
#include "ratchet/solver/nsgs.hpp"

namespace ratchet {

class AndersonMixer {
 public:
  static constexpr int kMaxDepth = kMaxAndersonDepth;  // solver.anderson_depth's upper bound (nsgs.hpp)
  // Reductions over the rows run in fixed blocks of this many rows (thread-independent
  // sums); the passes run in parallel above these sizes, below which a parallel region
  // costs more than it saves.
  static constexpr std::size_t kBlock = 512;
  // step_bound > 0: the extrapolation moves the impulses at most step_bound times as far
  // as the sweep did (|dG gamma| <= step_bound |G(x) - x|; 0: no bound). The rigid law
  // needs it: a jam has no solution, and an unbounded extrapolation of its growth makes
  // the impulses so large that the sweep's constant increment is lost in their round-off.
  // The arrays live in `buffers` (kept between solves: solver/anderson_buffers.hpp); a
  // mixer starts with no history whatever they hold.
  AndersonMixer(AndersonBuffers& buffers, int depth, int parallel_min_rows = kParallelMinRows,
                double step_bound = 0.0);

  // The sweep writes x_k (before) and G(x_k) (after) row by row into these contiguous
  // buffers (3 per row) while each row is in cache.
  double* record_buffer(std::size_t rows, bool after);

  // The body velocities after the sweep (v then w, 6 per body), recorded before plan():
  // they are linear in the impulses, v = v_free + M^-1 H lambda, so the same mix of
  // their history gives the velocities of the unprojected extrapolated impulses
  // without a pass over the rows.
  void record_velocities(const std::vector<Vec3>& v, const std::vector<Vec3>& w);

  // After the sweep: updates the history and returns whether to extrapolate;
  // extrapolated(k, mu) is then row k's new impulse, projected onto its cone, and
  // unprojected(k) the same before the projection.
  bool plan(const std::vector<SolverRow>& rows);
  Vec3 extrapolated(std::size_t k, double mu) const;
  Vec3 unprojected(std::size_t k) const { return Vec3(b_.raw[3 * k], b_.raw[3 * k + 1], b_.raw[3 * k + 2]); }
  // The body velocities of the unprojected impulses (needs record_velocities each sweep).
  void extrapolated_velocities(std::vector<Vec3>& v, std::vector<Vec3>& w) const;

  int restarts() const { return restarts_; }

 private:
  int depth_;
  int parallel_min_rows_;  // the passes run in parallel above this many rows (bodies: a quarter)
  double step_bound_;      // 0, or the bound on the extrapolation's step (constructor)
  bool bound_step(std::size_t n);  // scales gamma_ so that the step keeps step_bound_; true if it did
  AndersonBuffers& b_;         // the arrays (x, f, g, the ring of columns, ...), kept between solves
  Eigen::MatrixXd gram_;        // dF^T dF of the ring's columns
  Eigen::VectorXd rhs_;         // dF^T f_k
  bool weighted_ = false;       // b_.weight holds this solve's rows
  double gamma_[kMaxDepth] = {};              // the last plan's coefficients
  const double* gcols_[kMaxDepth] = {};       // and the dG columns they weigh
  const double* vcols_[kMaxDepth] = {};       // and the dV columns
  // x[i] = src[i] - sum over the plan's columns of gamma_a cols[a][i], in column order,
  // in blocks of 3 kBlock entries (in parallel if asked); x is not src.
  void subtract_columns(double* x, const double* src, std::size_t n, bool parallel, const double* const* cols) const;
  int count_ = 0, head_ = 0;
  bool have_prev_ = false;
  double fnorm_prev_ = 0.0;
  int restarts_ = 0;
};

}  // namespace ratchet
