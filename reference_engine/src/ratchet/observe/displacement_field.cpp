#include "ratchet/observe/displacement_field.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace ratchet {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Distance from the axis below which e_r is undefined (brief: r < 1e-12 gives u_r = 0).
constexpr double kOnAxis = 1e-12;

void check_grid(const char* where, double cell, int nr, int nz) {
  if (!std::isfinite(cell) || !(cell > 0.0)) throw std::invalid_argument(std::string(where) + ": cell size must be positive and finite");
  if (nr < 1 || nz < 1)
    throw std::invalid_argument(std::string(where) + ": grid must have at least 1 x 1 cells, got " + std::to_string(nr) +
                                " x " + std::to_string(nz));
}

}  // namespace

DisplacementField displacement_field(const std::vector<Vec3>& positions_a, const std::vector<Vec3>& positions_b,
                                     double cell, int nr, int nz) {
  return displacement_field(positions_a, positions_a, positions_b, cell, nr, nz);
}

DisplacementField displacement_field(const std::vector<Vec3>& reference, const std::vector<Vec3>& positions_a,
                                     const std::vector<Vec3>& positions_b, double cell, int nr, int nz) {
  constexpr const char* where = "displacement_field";
  check_grid(where, cell, nr, nz);
  if (positions_a.size() != positions_b.size() || reference.size() != positions_a.size())
    throw std::invalid_argument(std::string(where) + ": snapshots have " + std::to_string(reference.size()) + ", " +
                                std::to_string(positions_a.size()) + " and " + std::to_string(positions_b.size()) +
                                " particles");
  DisplacementField f;
  f.cell = cell;
  f.nr = nr;
  f.nz = nz;
  const auto cells = static_cast<std::size_t>(nr) * static_cast<std::size_t>(nz);
  f.ur.assign(cells, 0.0);
  f.uz.assign(cells, 0.0);
  f.count.assign(cells, 0);
  for (std::size_t i = 0; i < positions_a.size(); ++i) {
    const Vec3& a = reference[i];
    if (!a.allFinite() || !positions_a[i].allFinite() || !positions_b[i].allFinite())
      throw std::invalid_argument(std::string(where) + ": particle " + std::to_string(i) + " has a non-finite position");
    const Vec3 d = positions_b[i] - positions_a[i];
    const double r = std::hypot(a.x(), a.y());
    const double u_r = r < kOnAxis ? 0.0 : (d.x() * a.x() + d.y() * a.y()) / r;
    const double qr = std::floor(r / cell), qz = std::floor(a.z() / cell);
    if (qz < 0.0 || qr >= nr || qz >= nz) continue;  // outside the grid
    const int k = f.index(static_cast<int>(qr), static_cast<int>(qz));
    f.ur[static_cast<std::size_t>(k)] += u_r;
    f.uz[static_cast<std::size_t>(k)] += d.z();
    ++f.count[static_cast<std::size_t>(k)];
  }
  for (std::size_t k = 0; k < cells; ++k) {
    if (f.count[k] > 0) {
      f.ur[k] /= f.count[k];
      f.uz[k] /= f.count[k];
    } else {
      f.ur[k] = f.uz[k] = kNaN;
    }
  }
  return f;
}

DisplacementField field_from_values(double cell, int nr, int nz, std::vector<double> ur, std::vector<double> uz,
                                    std::vector<int> count) {
  constexpr const char* where = "field_from_values";
  check_grid(where, cell, nr, nz);
  const auto cells = static_cast<std::size_t>(nr) * static_cast<std::size_t>(nz);
  if (ur.size() != cells || uz.size() != cells || count.size() != cells)
    throw std::invalid_argument(std::string(where) + ": arrays must have nr * nz = " + std::to_string(cells) + " entries");
  for (int c : count)
    if (c < 0) throw std::invalid_argument(std::string(where) + ": negative cell count");
  DisplacementField f;
  f.cell = cell;
  f.nr = nr;
  f.nz = nz;
  f.ur = std::move(ur);
  f.uz = std::move(uz);
  f.count = std::move(count);
  return f;
}

VorticityField vorticity_field(const DisplacementField& f) {
  const auto cells = static_cast<std::size_t>(f.nr) * static_cast<std::size_t>(f.nz);
  if (f.ur.size() != cells || f.uz.size() != cells || f.count.size() != cells || !(f.cell > 0.0))
    throw std::invalid_argument("vorticity_field: inconsistent displacement field");
  VorticityField v;
  v.w.assign(cells, kNaN);
  v.interior.assign(cells, 0);
  auto at = [&](int ir, int iz) { return static_cast<std::size_t>(f.index(ir, iz)); };
  const double h2 = 2.0 * f.cell;
  for (int iz = 1; iz + 1 < f.nz; ++iz)
    for (int ir = 1; ir + 1 < f.nr; ++ir) {
      const std::size_t c = at(ir, iz), e = at(ir + 1, iz), w = at(ir - 1, iz), n = at(ir, iz + 1), s = at(ir, iz - 1);
      if (f.count[c] <= 0 || f.count[e] <= 0 || f.count[w] <= 0 || f.count[n] <= 0 || f.count[s] <= 0) continue;
      v.interior[c] = 1;
      v.w[c] = (f.uz[e] - f.uz[w]) / h2 - (f.ur[n] - f.ur[s]) / h2;
    }
  return v;
}

double rms_vorticity(const VorticityField& v) {
  if (v.w.size() != v.interior.size()) throw std::invalid_argument("rms_vorticity: inconsistent vorticity field");
  double sum = 0.0;
  int n = 0;
  for (std::size_t k = 0; k < v.w.size(); ++k)
    if (v.interior[k]) sum += v.w[k] * v.w[k], ++n;
  return n > 0 ? std::sqrt(sum / n) : kNaN;
}

}  // namespace ratchet
