#include "ratchet/solver/anderson.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace ratchet {

void AndersonMixer::begin(const std::vector<SolverRow>& rows) {
  x_.resize(3 * rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k)
    for (int j = 0; j < 3; ++j) x_[3 * k + static_cast<std::size_t>(j)] = rows[k].lambda[j];
}

bool AndersonMixer::mix(std::vector<SolverRow>& rows) {
  const std::size_t n = 3 * rows.size();
  f_.resize(n);
  g_.resize(n);
  double fnorm = 0.0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const double wk = std::sqrt(rows[k].W(0, 0));
    for (int j = 0; j < 3; ++j) {
      const std::size_t i = 3 * k + static_cast<std::size_t>(j);
      g_[i] = rows[k].lambda[j];
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
    }
    const int h = head_;
    count_ = std::min(count_ + 1, depth_);
    head_ = (head_ + 1) % depth_;
    std::vector<double>& cf = dF_[static_cast<std::size_t>(h)];
    std::vector<double>& cg = dG_[static_cast<std::size_t>(h)];
    cf.resize(n);
    cg.resize(n);
    // The new column and its row of the Gram matrix in one pass (the other entries
    // are kept from earlier sweeps): 2m products per unknown instead of m^2 / 2.
    double dots[kMaxDepth] = {};
    for (std::size_t i = 0; i < n; ++i) {
      const double c = f_[i] - f_prev_[i];
      cf[i] = c;
      cg[i] = g_[i] - g_prev_[i];
      for (int b = 0; b < count_; ++b) dots[b] += c * (b == h ? c : dF_[static_cast<std::size_t>(b)][i]);
    }
    for (int b = 0; b < count_; ++b) { gram_(h, b) = dots[b]; gram_(b, h) = dots[b]; }
  }
  f_prev_ = f_;
  g_prev_ = g_;
  fnorm_prev_ = fnorm;
  have_prev_ = true;
  if (count_ == 0) return false;
  // Least squares by the normal equations of the m columns (m <= depth, small), summed
  // in a fixed order so the result does not depend on threads.
  const int m = count_;
  Eigen::VectorXd r = Eigen::VectorXd::Zero(m);
  for (std::size_t i = 0; i < n; ++i)
    for (int a = 0; a < m; ++a) r(a) += dF_[static_cast<std::size_t>(a)][i] * f_[i];
  Eigen::MatrixXd G = gram_.topLeftCorner(m, m);
  // Tikhonov term relative to the Gram matrix's scale: keeps nearly parallel columns
  // (a slowly converging sweep repeats its direction) from blowing gamma up.
  G.diagonal().array() += 1e-10 * G.diagonal().maxCoeff() + 1e-300;
  const Eigen::VectorXd gamma = G.ldlt().solve(r);
  if (!gamma.allFinite()) { count_ = 0; head_ = 0; ++restarts_; return false; }
  for (std::size_t k = 0; k < rows.size(); ++k) {
    Vec3 l;
    for (int j = 0; j < 3; ++j) {
      const std::size_t i = 3 * k + static_cast<std::size_t>(j);
      double v = g_[i];
      for (int a = 0; a < m; ++a) v -= gamma(a) * dG_[static_cast<std::size_t>(a)][i];
      l[j] = v;
    }
    // Back onto the cone: lambda_n >= 0, |lambda_t| <= mu lambda_n.
    l[0] = std::max(0.0, l[0]);
    const double lt = std::sqrt(l[1] * l[1] + l[2] * l[2]), cap = rows[k].mu * l[0];
    if (lt > cap) {
      const double f = lt > 0.0 ? cap / lt : 0.0;
      l[1] *= f;
      l[2] *= f;
    }
    rows[k].lambda = l;
  }
  return true;
}

}  // namespace ratchet
