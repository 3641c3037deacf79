#include "ratchet/solver/anderson.hpp"

#include "ratchet/solver/local_coulomb.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace ratchet {

namespace {

// Tikhonov term on the Gram matrix's diagonal, relative to its largest entry: it matters
// only for eigenvalues below about 1e-10 of the largest, i.e. combinations of the
// columns shorter than about 1e-5 of the longest (nearly parallel columns). The absolute
// term (squared velocity units) keeps the matrix positive definite when every column is zero.
constexpr double kTikhonovRel = 1e-10;
constexpr double kTikhonovFloor = 1e-300;

// The pass of plan() that makes the new column of dF and dG and its dot products, over
// entries [i0, i1): out[0] = the column . f_{k-1}, out[1 + b] = the column . column b.
// Every sum is accumulated entry by entry in order, whatever the depth: the same bits
// from the template (depth known, sums kept in registers) and from the loop below.
struct NewColumn {
  const double *f, *f_prev, *g, *g_prev;
  double *cf, *cg;             // the new columns (cf is also one of cols)
  const double* const* cols;   // the dF columns, the new one included
};

// M > 0: the depth known when compiled (the sums stay in registers); M = 0: any depth m.
template <int M>
void new_column_block(const NewColumn& p, int m, std::size_t i0, std::size_t i1, double* out) {
  constexpr int kSlots = M > 0 ? M : kMaxAndersonDepth;
  const int count = M > 0 ? M : m;
  double dots[kSlots] = {};
  const double* cols[kSlots];
  for (int b = 0; b < count; ++b) cols[b] = p.cols[b];
  double with_prev = 0.0;
  for (std::size_t i = i0; i < i1; ++i) {
    const double c = p.f[i] - p.f_prev[i];
    p.cf[i] = c;
    p.cg[i] = p.g[i] - p.g_prev[i];
    with_prev += c * p.f_prev[i];
    for (int b = 0; b < count; ++b) dots[b] += c * cols[b][i];  // the new column: c * c
  }
  out[0] = with_prev;
  for (int b = 0; b < count; ++b) out[1 + b] = dots[b];
}

// x[i] = src[i] - gamma_a cols[a][i] for a = 0, 1, ... in that order, entry by entry:
// the same operations on each entry as a copy and then a pass per column, with the entry
// loaded and stored once (a pass per column cost 3.7 instructions per entry and column,
// callgrind). M > 0: the number of columns known when compiled; M = 0: any count m.
template <int M>
void subtract_block(double* __restrict x, const double* __restrict src, std::size_t i0, std::size_t i1,
                    const double* gamma, const double* const* cols, int m) {
  constexpr int kSlots = M > 0 ? M : kMaxAndersonDepth;
  const int count = M > 0 ? M : m;
  double g[kSlots];
  const double* __restrict c[kSlots];
  for (int a = 0; a < count; ++a) { g[a] = gamma[a]; c[a] = cols[a]; }
  for (std::size_t i = i0; i < i1; ++i) {
    double xi = src[i];
    for (int a = 0; a < count; ++a) xi -= g[a] * c[a][i];
    x[i] = xi;
  }
}

}  // namespace

AndersonMixer::AndersonMixer(AndersonBuffers& buffers, int depth, int parallel_min_rows, double step_bound)
    : depth_(depth < kMaxDepth ? depth : kMaxDepth),
      parallel_min_rows_(parallel_min_rows),
      step_bound_(step_bound),
      b_(buffers) {
  if (depth_ > 0) {
    gram_ = Eigen::MatrixXd::Zero(depth_, depth_);
    rhs_ = Eigen::VectorXd::Zero(depth_);
  }
}

double* AndersonMixer::record_buffer(std::size_t rows, bool after) {
  std::vector<double>& b = after ? b_.g : b_.x;
  b.resize(3 * rows);
  return b.data();
}

void AndersonMixer::record_velocities(const std::vector<Vec3>& v, const std::vector<Vec3>& w) {
  const std::size_t n = v.size();
  b_.vel.resize(6 * n);
#pragma omp parallel for schedule(static) if (static_cast<int>(n) > parallel_min_rows_ / 4)
  for (std::size_t i = 0; i < n; ++i)
    for (int j = 0; j < 3; ++j) {
      b_.vel[6 * i + static_cast<std::size_t>(j)] = v[i][j];
      b_.vel[6 * i + 3 + static_cast<std::size_t>(j)] = w[i][j];
    }
}

void AndersonMixer::extrapolated_velocities(std::vector<Vec3>& v, std::vector<Vec3>& w) const {
  const std::size_t n = v.size();
  // Each entry minus its products in the order of the columns (subtract_block).
  std::vector<double>& x = b_.vel_mix;
  x.resize(6 * n);  // the velocities of G(x_k) minus the mix of the dV columns
  subtract_columns(x.data(), b_.vel_prev.data(), 6 * n, n > static_cast<std::size_t>(parallel_min_rows_ / 4), vcols_);
#pragma omp parallel for schedule(static) if (static_cast<int>(n) > parallel_min_rows_ / 4)
  for (std::size_t i = 0; i < n; ++i)
    for (int j = 0; j < 3; ++j) {
      v[i][j] = x[6 * i + static_cast<std::size_t>(j)];
      w[i][j] = x[6 * i + 3 + static_cast<std::size_t>(j)];
    }
}

void AndersonMixer::subtract_columns(double* x, const double* src, std::size_t n, bool parallel,
                                     const double* const* cols) const {
  const int nblocks = static_cast<int>((n + 3 * kBlock - 1) / (3 * kBlock));
#pragma omp parallel for schedule(static) if (parallel)
  for (int blk = 0; blk < nblocks; ++blk) {
    const std::size_t i0 = 3 * kBlock * static_cast<std::size_t>(blk), i1 = std::min(n, i0 + 3 * kBlock);
    switch (count_) {  // the usual depths with the entry kept in a register across the columns
      case 1: subtract_block<1>(x, src, i0, i1, gamma_, cols, 1); break;
      case 2: subtract_block<2>(x, src, i0, i1, gamma_, cols, 2); break;
      case 3: subtract_block<3>(x, src, i0, i1, gamma_, cols, 3); break;
      case 4: subtract_block<4>(x, src, i0, i1, gamma_, cols, 4); break;
      case 5: subtract_block<5>(x, src, i0, i1, gamma_, cols, 5); break;
      default: subtract_block<0>(x, src, i0, i1, gamma_, cols, count_);
    }
  }
}

// The step taken, |G(x_k) - raw|, against the sweep's own, |G(x_k) - x_k|, entry by entry
// in order (one thread: it runs only for the rigid law, where the sweeps, not this pass,
// are the cost). True when gamma_ was scaled down and b_.raw must be mixed again.
bool AndersonMixer::bound_step(std::size_t n) {
  double step2 = 0.0, move2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double d = b_.g_prev[i] - b_.x[i], c = b_.g_prev[i] - b_.raw[i];
    step2 += d * d;
    move2 += c * c;
  }
  const double limit = step_bound_ * std::sqrt(step2), move = std::sqrt(move2);
  if (!(move > limit)) return false;
  const double scale = limit / move;
  for (int a = 0; a < count_; ++a) gamma_[a] *= scale;
  return true;
}

Vec3 AndersonMixer::extrapolated(std::size_t k, double mu) const { return project_onto_cone(unprojected(k), mu); }

bool AndersonMixer::plan(const std::vector<SolverRow>& rows) {
  const std::size_t n = 3 * rows.size();
  if (!weighted_) {  // W is fixed within a solve: one pass for all sweeps
    b_.weight.resize(rows.size());
    for (std::size_t k = 0; k < rows.size(); ++k) b_.weight[k] = std::sqrt(rows[k].W(0, 0));
    weighted_ = true;
  }
  b_.f.resize(n);
  // Sums over the unknowns in fixed blocks of kBlock rows, added in block order: the same
  // bits for any number of threads.
  const std::size_t rows_n = rows.size();
  const int nblocks = static_cast<int>((rows_n + kBlock - 1) / kBlock);
  b_.partial.assign(static_cast<std::size_t>(nblocks) * (kMaxDepth + 2), 0.0);
  double* part = b_.partial.data();
  const bool parallel = static_cast<int>(rows_n) > parallel_min_rows_;
#pragma omp parallel for schedule(static) if (parallel)
  for (int blk = 0; blk < nblocks; ++blk) {
    double sum = 0.0;
    const std::size_t k1 = std::min(rows_n, (static_cast<std::size_t>(blk) + 1) * kBlock);
    for (std::size_t k = static_cast<std::size_t>(blk) * kBlock; k < k1; ++k) {
      const double wk = b_.weight[k];
      for (int j = 0; j < 3; ++j) {
        const std::size_t i = 3 * k + static_cast<std::size_t>(j);
        b_.f[i] = wk * (b_.g[i] - b_.x[i]);
        sum += b_.f[i] * b_.f[i];
      }
    }
    part[static_cast<std::size_t>(blk) * (kMaxDepth + 2)] = sum;
  }
  double fnorm = 0.0;
  for (int blk = 0; blk < nblocks; ++blk) fnorm += part[static_cast<std::size_t>(blk) * (kMaxDepth + 2)];
  fnorm = std::sqrt(fnorm);
  const bool restart = have_prev_ && fnorm > fnorm_prev_;
  if (restart) { count_ = 0; head_ = 0; ++restarts_; }
  if (have_prev_ && !restart && b_.f_prev.size() == n) {
    if (b_.dF.size() < static_cast<std::size_t>(depth_)) {
      b_.dF.resize(static_cast<std::size_t>(depth_));
      b_.dG.resize(b_.dF.size());
      b_.dV.resize(b_.dF.size());
    }
    const int h = head_;
    count_ = std::min(count_ + 1, depth_);
    head_ = (head_ + 1) % depth_;
    std::vector<double>& cf = b_.dF[static_cast<std::size_t>(h)];
    std::vector<double>& cg = b_.dG[static_cast<std::size_t>(h)];
    cf.resize(n);
    cg.resize(n);
    // The new column, its row of the Gram matrix and its product with b_.f{k-1} in one
    // pass; the other entries are kept from earlier sweeps. Since f_k = b_.f{k-1} + the
    // new column, the right-hand side dF^T f_k follows from the last one and the new
    // Gram row without another pass: 2m + 1 products per unknown in all.
    const double* cols[kMaxDepth];
    for (int b = 0; b < count_; ++b) cols[b] = b_.dF[static_cast<std::size_t>(b)].data();
    double* cfp = cf.data();
    double* cgp = cg.data();
    const int m = count_;
    const std::size_t stride = kMaxDepth + 2;
#pragma omp parallel for schedule(static) if (parallel)
    for (int blk = 0; blk < nblocks; ++blk) {
      const std::size_t i0 = 3 * static_cast<std::size_t>(blk) * kBlock;
      const std::size_t i1 = 3 * std::min(rows_n, (static_cast<std::size_t>(blk) + 1) * kBlock);
      const NewColumn pass{b_.f.data(), b_.f_prev.data(), b_.g.data(), b_.g_prev.data(), cfp, cgp, cols};
      double* out = part + static_cast<std::size_t>(blk) * stride;
      switch (m) {  // the usual depths with the sums in registers
        case 1: new_column_block<1>(pass, m, i0, i1, out); break;
        case 2: new_column_block<2>(pass, m, i0, i1, out); break;
        case 3: new_column_block<3>(pass, m, i0, i1, out); break;
        case 4: new_column_block<4>(pass, m, i0, i1, out); break;
        case 5: new_column_block<5>(pass, m, i0, i1, out); break;
        default: new_column_block<0>(pass, m, i0, i1, out);
      }
    }
    double dots[kMaxDepth] = {};
    double with_prev = 0.0;
    for (int blk = 0; blk < nblocks; ++blk) {
      const double* in = part + static_cast<std::size_t>(blk) * stride;
      with_prev += in[0];
      for (int b = 0; b < m; ++b) dots[b] += in[1 + b];
    }
    if (!b_.vel.empty() && b_.vel_prev.size() == b_.vel.size()) {
      std::vector<double>& cv = b_.dV[static_cast<std::size_t>(h)];
      cv.resize(b_.vel.size());
      const double* vp = b_.vel.data();
      const double* vq = b_.vel_prev.data();
      double* cvp = cv.data();
      const int nv = static_cast<int>(b_.vel.size());
#pragma omp parallel for schedule(static) if (parallel)
      for (int i = 0; i < nv; ++i) cvp[i] = vp[i] - vq[i];
    }
    for (int b = 0; b < count_; ++b) { gram_(h, b) = dots[b]; gram_(b, h) = dots[b]; }
    for (int b = 0; b < count_; ++b) rhs_(b) = b == h ? with_prev + dots[h] : rhs_(b) + dots[b];
  }
  b_.f_prev.swap(b_.f);
  b_.g_prev.swap(b_.g);
  b_.vel_prev.swap(b_.vel);
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
  G.diagonal().array() += kTikhonovRel * G.diagonal().maxCoeff() + kTikhonovFloor;
  const Eigen::VectorXd gamma = G.ldlt().solve(r);
  if (!gamma.allFinite()) { count_ = 0; head_ = 0; ++restarts_; return false; }
  for (int a = 0; a < m; ++a) {
    gamma_[a] = gamma(a);
    gcols_[a] = b_.dG[static_cast<std::size_t>(a)].data();
    vcols_[a] = b_.dV[static_cast<std::size_t>(a)].data();
  }
  b_.raw.resize(n);  // G(x_k) minus the mix of the dG columns
  subtract_columns(b_.raw.data(), b_.g_prev.data(), n, parallel, gcols_);
  if (step_bound_ > 0.0 && bound_step(n)) subtract_columns(b_.raw.data(), b_.g_prev.data(), n, parallel, gcols_);
  return true;
}

}  // namespace ratchet
