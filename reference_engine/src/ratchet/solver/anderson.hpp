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

#include "ratchet/solver/nsgs.hpp"

namespace ratchet {

class AndersonMixer {
 public:
  static constexpr int kMaxDepth = 50;  // solver.anderson_depth's upper bound
  explicit AndersonMixer(int depth) : depth_(depth < kMaxDepth ? depth : kMaxDepth) {}

  // The sweep writes x_k (before) and G(x_k) (after) row by row into these contiguous
  // buffers (3 per row) while each row is in cache.
  double* record_buffer(std::size_t rows, bool after);

  // After the sweep: updates the history and returns whether to extrapolate;
  // extrapolated(k, mu) is then row k's new impulse, projected onto its cone (the caller
  // writes it and rebuilds the body velocities in the same pass).
  bool plan(const std::vector<SolverRow>& rows);
  Vec3 extrapolated(std::size_t k, double mu) const;

  int restarts() const { return restarts_; }

 private:
  int depth_;
  std::vector<double> x_, f_prev_, g_prev_, f_, g_;
  std::vector<std::vector<double>> dF_, dG_;  // ring buffers of columns
  Eigen::MatrixXd gram_;                      // dF^T dF of the ring's columns
  Eigen::VectorXd rhs_;                       // dF^T f_k
  std::vector<double> weight_;                // sqrt(W_nn) per row
  double gamma_[kMaxDepth] = {};              // the last plan's coefficients
  const double* gcols_[kMaxDepth] = {};       // and the dG columns they weigh
  int count_ = 0, head_ = 0;
  bool have_prev_ = false;
  double fnorm_prev_ = 0.0;
  int restarts_ = 0;
};

}  // namespace ratchet
