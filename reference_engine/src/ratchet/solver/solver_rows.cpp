#include "ratchet/solver/solver_rows.hpp"

namespace ratchet {

double velocity_change(const SolverBodies& B, const std::vector<Vec3>& v0, const std::vector<Vec3>& w0,
                       bool rotation) {
  return velocity_change(B, B.v, B.w, v0, w0, rotation);
}

double velocity_change(const SolverBodies& B, const std::vector<Vec3>& v, const std::vector<Vec3>& w,
                       const std::vector<Vec3>& v0, const std::vector<Vec3>& w0, bool rotation) {
  double e = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (B.mass[i] == 0.0) continue;  // fixed
    e += B.mass[i] * (v[i] - v0[i]).squaredNorm();
    if (rotation) {
      const double sc = B.scale[i];
      const Vec3 dw = B.R[i].transpose() * (w[i] - w0[i]);
      e += (sc * sc) * dw.dot(B.principal_inertia[i].cwiseProduct(dw));
    }
  }
  return e;
}

double normal_impulse_sum(const std::vector<SolverRow>& rows) {
  double sum = 0.0;
  for (const SolverRow& c : rows) sum += c.lambda[0];
  return sum;
}

}  // namespace ratchet
