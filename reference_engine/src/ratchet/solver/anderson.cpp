#include "ratchet/solver/anderson.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace ratchet {

double* AndersonMixer::record_buffer(std::size_t rows, bool after) {
  std::vector<double>& b = after ? g_ : x_;
  b.resize(3 * rows);
  return b.data();
}

Vec3 AndersonMixer::extrapolated(std::size_t k, double mu) const {
  Vec3 l;
  for (int j = 0; j < 3; ++j) {
    const std::size_t i = 3 * k + static_cast<std::size_t>(j);
    double v = g_prev_[i];  // G(x_k), swapped in by plan()
    for (int a = 0; a < count_; ++a) v -= gamma_[a] * gcols_[a][i];
    l[j] = v;
  }
  // Back onto the cone: lambda_n >= 0, |lambda_t| <= mu lambda_n.
  l[0] = std::max(0.0, l[0]);
  const double lt = std::sqrt(l[1] * l[1] + l[2] * l[2]), cap = mu * l[0];
  if (lt > cap) {
    const double f = lt > 0.0 ? cap / lt : 0.0;
    l[1] *= f;
    l[2] *= f;
  }
  return l;
}

bool AndersonMixer::plan(const std::vector<SolverRow>& rows) {
  const std::size_t n = 3 * rows.size();
  if (weight_.size() != rows.size()) {  // W is fixed within a solve: one pass for all sweeps
    weight_.resize(rows.size());
    for (std::size_t k = 0; k < rows.size(); ++k) weight_[k] = std::sqrt(rows[k].W(0, 0));
  }
  f_.resize(n);
  double fnorm = 0.0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const double wk = weight_[k];
    for (int j = 0; j < 3; ++j) {
      const std::size_t i = 3 * k + static_cast<std::size_t>(j);
      f_[i] = wk * (g_[i] - x_[i]);
      fnorm += f_[i] * f_[i];
    }
  }
  fnorm = std::sqrt(fnorm);
  const bool restart = have_prev_ && fnorm > fnorm_prev_;
  if (restart) { count_ = 0; head_ = 0; ++restarts_; }
  if (have_prev_ && !restart && f_prev_.size() == n) {
    if (dF_.size() < static_cast<std::size_t>(depth_)) {
      dF_.resize(static_cast<std::size_t>(depth_));
      dG_.resize(dF_.size());
      gram_ = Eigen::MatrixXd::Zero(depth_, depth_);
      rhs_ = Eigen::VectorXd::Zero(depth_);
    }
    const int h = head_;
    count_ = std::min(count_ + 1, depth_);
    head_ = (head_ + 1) % depth_;
    std::vector<double>& cf = dF_[static_cast<std::size_t>(h)];
    std::vector<double>& cg = dG_[static_cast<std::size_t>(h)];
    cf.resize(n);
    cg.resize(n);
    // The new column, its row of the Gram matrix and its product with f_{k-1} in one
    // pass; the other entries are kept from earlier sweeps. Since f_k = f_{k-1} + the
    // new column, the right-hand side dF^T f_k follows from the last one and the new
    // Gram row without another pass: 2m + 1 products per unknown in all.
    const double* cols[kMaxDepth];
    for (int b = 0; b < count_; ++b) cols[b] = dF_[static_cast<std::size_t>(b)].data();
    double dots[kMaxDepth] = {};
    double with_prev = 0.0;
    double* cfp = cf.data();
    double* cgp = cg.data();
    for (std::size_t i = 0; i < n; ++i) {
      const double c = f_[i] - f_prev_[i];
      cfp[i] = c;
      cgp[i] = g_[i] - g_prev_[i];
      with_prev += c * f_prev_[i];
      for (int b = 0; b < count_; ++b) dots[b] += c * cols[b][i];  // cols[h] is cfp: c * c
    }
    for (int b = 0; b < count_; ++b) { gram_(h, b) = dots[b]; gram_(b, h) = dots[b]; }
    for (int b = 0; b < count_; ++b) rhs_(b) = b == h ? with_prev + dots[h] : rhs_(b) + dots[b];
  }
  f_prev_.swap(f_);
  g_prev_.swap(g_);
  fnorm_prev_ = fnorm;
  have_prev_ = true;
  if (count_ == 0) return false;
  // Least squares by the normal equations of the m columns (m <= depth, small), summed
  // in a fixed order so the result does not depend on threads.
  const int m = count_;
  const Eigen::VectorXd r = rhs_.head(m);
  Eigen::MatrixXd G = gram_.topLeftCorner(m, m);
  // Tikhonov term relative to the Gram matrix's scale: keeps nearly parallel columns
  // (a slowly converging sweep repeats its direction) from blowing gamma up.
  G.diagonal().array() += 1e-10 * G.diagonal().maxCoeff() + 1e-300;
  const Eigen::VectorXd gamma = G.ldlt().solve(r);
  if (!gamma.allFinite()) { count_ = 0; head_ = 0; ++restarts_; return false; }
  for (int a = 0; a < m; ++a) {
    gamma_[a] = gamma(a);
    gcols_[a] = dG_[static_cast<std::size_t>(a)].data();
  }
  return true;
}

}  // namespace ratchet
