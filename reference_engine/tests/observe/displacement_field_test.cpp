#include "ratchet/observe/displacement_field.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <vector>

namespace ratchet {
namespace {

// Every cell populated with an analytic field sampled at the cell centre
// ((ir + 1/2) h, (iz + 1/2) h).
DisplacementField sampled(double h, int nr, int nz, const std::function<double(double, double)>& ur,
                          const std::function<double(double, double)>& uz) {
  std::vector<double> a, b;
  for (int iz = 0; iz < nz; ++iz)
    for (int ir = 0; ir < nr; ++ir) {
      const double r = (ir + 0.5) * h, z = (iz + 0.5) * h;
      a.push_back(ur(r, z));
      b.push_back(uz(r, z));
    }
  return field_from_values(h, nr, nz, a, b, std::vector<int>(a.size(), 1));
}

bool on_grid_boundary(const DisplacementField& f, int ir, int iz) {
  return ir == 0 || iz == 0 || ir == f.nr - 1 || iz == f.nz - 1;
}

TEST(CylindricalMapping, RadialMoveOfAParticleAtOneOne) {
  // Particle at (x, y) = (1, 1), moved radially outwards by 0.1 and up by 0.05.
  const Vec3 a(1.0, 1.0, 0.3), er = Vec3(1.0, 1.0, 0.0).normalized();
  const Vec3 b = a + 0.1 * er + Vec3(0.0, 0.0, 0.05);
  const DisplacementField f = displacement_field({a}, {b}, 0.5, 4, 2);
  // r = sqrt 2 = 1.414 -> ir = 2; z = 0.3 -> iz = 0.
  const auto k = static_cast<std::size_t>(f.index(2, 0));
  EXPECT_EQ(f.count[k], 1);
  // 1e-15: one dot product of O(1) numbers.
  EXPECT_NEAR(f.ur[k], 0.1, 1e-15);
  EXPECT_NEAR(f.uz[k], 0.05, 1e-15);
  // Every other cell is empty: NaN and count 0.
  for (std::size_t j = 0; j < f.count.size(); ++j)
    if (j != k) {
      EXPECT_EQ(f.count[j], 0) << j;
      EXPECT_TRUE(std::isnan(f.ur[j]) && std::isnan(f.uz[j])) << j;
    }
}

TEST(CylindricalMapping, IntervalsBinnedAtOneReferenceAddUpToTheWhole) {
  // Heating a -> b, cooling b -> c, both binned where the particles were at a (the stage
  // fields of run/stage_fields.hpp): cell by cell they add up to the field a -> c, even
  // for a particle that crossed into another cell at b and for radial components taken
  // at a (not at b).
  const std::vector<Vec3> a = {{0.9, 0.0, 0.2}, {0.0, 1.6, 0.7}, {-1.2, -0.3, 1.4}};
  const std::vector<Vec3> b = {{1.3, 0.2, 0.1}, {0.1, 1.5, 0.9}, {-1.1, -0.2, 1.3}};
  const std::vector<Vec3> c = {{1.0, 0.1, 0.25}, {-0.2, 1.7, 0.6}, {-1.3, -0.4, 1.5}};
  const DisplacementField heat = displacement_field(a, a, b, 1.0, 3, 3);
  const DisplacementField cool = displacement_field(a, b, c, 1.0, 3, 3);
  const DisplacementField whole = displacement_field(a, c, 1.0, 3, 3);
  for (std::size_t k = 0; k < whole.count.size(); ++k) {
    EXPECT_EQ(heat.count[k], whole.count[k]) << k;
    EXPECT_EQ(cool.count[k], whole.count[k]) << k;
    if (whole.count[k] == 0) continue;
    // 1e-15: two sums of O(1) differences.
    EXPECT_NEAR(heat.ur[k] + cool.ur[k], whole.ur[k], 1e-15) << k;
    EXPECT_NEAR(heat.uz[k] + cool.uz[k], whole.uz[k], 1e-15) << k;
  }
  // The particle at (0.9, 0, 0.2) is in cell (0, 0) at a, in (1, 0) at b: binned at a.
  EXPECT_EQ(cool.count[static_cast<std::size_t>(cool.index(0, 0))], 1);
  EXPECT_THROW(displacement_field({a[0]}, a, c, 1.0, 3, 3), std::invalid_argument);
}

TEST(CylindricalMapping, TangentialMoveHasNoRadialPartAndCellsAverage) {
  // Two particles in one cell on opposite sides of the axis, each moved along its own
  // -e_r by 0.2 and 0.4: u_r averages to -0.3. A third, moved tangentially, in another cell.
  const std::vector<Vec3> a = {{2.1, 0.0, 1.1}, {-2.2, 0.0, 1.2}, {0.0, 3.5, 1.5}};
  const std::vector<Vec3> b = {{1.9, 0.0, 1.1}, {-1.8, 0.0, 1.0}, {0.3, 3.5, 1.5}};
  const DisplacementField f = displacement_field(a, b, 1.0, 5, 3);
  const auto k = static_cast<std::size_t>(f.index(2, 1));
  EXPECT_EQ(f.count[k], 2);
  EXPECT_NEAR(f.ur[k], -0.3, 1e-15);         // 1e-15: rounding of a two-term mean
  EXPECT_NEAR(f.uz[k], -0.1, 1e-15);         // (0 - 0.2) / 2
  const auto t = static_cast<std::size_t>(f.index(3, 1));
  EXPECT_EQ(f.count[t], 1);
  EXPECT_NEAR(f.ur[t], 0.0, 1e-15);          // d is orthogonal to e_r = (0, 1, 0)
}

TEST(CylindricalMapping, AxisParticlesContributeOnlyVerticallyAndOutsideParticlesAreDropped) {
  const std::vector<Vec3> a = {{0.0, 0.0, 0.5}, {0.5, 0.0, -0.1}, {9.0, 0.0, 0.5}, {0.5, 0.0, 7.0}};
  const std::vector<Vec3> b = {{0.3, 0.4, 0.7}, {0.6, 0.0, -0.1}, {9.1, 0.0, 0.5}, {0.6, 0.0, 7.0}};
  const DisplacementField f = displacement_field(a, b, 1.0, 3, 3);
  int total = 0;
  for (int c : f.count) total += c;
  EXPECT_EQ(total, 1);  // z < 0, r beyond 3 cells, z beyond 3 cells are left out
  const auto k = static_cast<std::size_t>(f.index(0, 0));
  EXPECT_EQ(f.count[k], 1);
  EXPECT_EQ(f.ur[k], 0.0);
  EXPECT_NEAR(f.uz[k], 0.2, 1e-15);  // 1e-15: one subtraction
}

TEST(CylindricalMapping, RejectsBadInput) {
  EXPECT_THROW(displacement_field({Vec3::Zero()}, {}, 1.0, 2, 2), std::invalid_argument);
  EXPECT_THROW(displacement_field({}, {}, 0.0, 2, 2), std::invalid_argument);
  EXPECT_THROW(displacement_field({}, {}, 1.0, 0, 2), std::invalid_argument);
  EXPECT_THROW(displacement_field({Vec3(std::nan(""), 0, 0)}, {Vec3::Zero()}, 1.0, 2, 2), std::invalid_argument);
  EXPECT_THROW(field_from_values(1.0, 2, 2, {0, 0, 0}, {0, 0, 0, 0}, {1, 1, 1, 1}), std::invalid_argument);
  EXPECT_THROW(field_from_values(1.0, 1, 1, {0}, {0}, {-1}), std::invalid_argument);
}

TEST(Vorticity, RigidRotationIsTwiceOmegaOnInteriorCells) {
  // u = Omega x r in the (r, z) plane about (r0, z0): u_r = -Omega (z - z0),
  // u_z = Omega (r - r0), so w = du_z/dr - du_r/dz = 2 Omega.
  const double omega = 0.37, r0 = 3.1, z0 = 4.3, h = 0.5;
  const DisplacementField f = sampled(
      h, 12, 16, [&](double, double z) { return -omega * (z - z0); }, [&](double r, double) { return omega * (r - r0); });
  const VorticityField v = vorticity_field(f);
  int interior = 0;
  for (int iz = 0; iz < f.nz; ++iz)
    for (int ir = 0; ir < f.nr; ++ir) {
      const auto k = static_cast<std::size_t>(f.index(ir, iz));
      if (on_grid_boundary(f, ir, iz)) {
        EXPECT_FALSE(v.interior[k]) << ir << ',' << iz;
        EXPECT_TRUE(std::isnan(v.w[k])) << ir << ',' << iz;
      } else {
        ++interior;
        EXPECT_TRUE(v.interior[k]) << ir << ',' << iz;
        // 1e-13: central differences are exact for a linear field; rounding of
        // differences of O(1) values divided by 2h = 1 remains.
        EXPECT_NEAR(v.w[k], 2.0 * omega, 1e-13) << ir << ',' << iz;
      }
    }
  EXPECT_EQ(interior, 10 * 14);
  EXPECT_NEAR(rms_vorticity(v), 2.0 * omega, 1e-13);  // same reason
}

TEST(Vorticity, IrrotationalFieldsHaveZeroVorticity) {
  const double h = 0.25;
  // u = grad phi, phi = r^2 - z^2: u_r = 2r, u_z = -2z.
  const VorticityField a = vorticity_field(
      sampled(h, 9, 7, [](double r, double) { return 2.0 * r; }, [](double, double z) { return -2.0 * z; }));
  // phi = r^2 z - z^3/3: u_r = 2 r z, u_z = r^2 - z^2; both cross derivatives are 2r,
  // and central differences are exact for quadratics, so the two terms cancel.
  const VorticityField b = vorticity_field(sampled(
      h, 9, 7, [](double r, double z) { return 2.0 * r * z; }, [](double r, double z) { return r * r - z * z; }));
  // Uniform translation.
  const VorticityField c =
      vorticity_field(sampled(h, 9, 7, [](double, double) { return 0.7; }, [](double, double) { return -1.3; }));
  for (const VorticityField* v : {&a, &b, &c}) {
    int interior = 0;
    for (std::size_t k = 0; k < v->w.size(); ++k)
      if (v->interior[k]) {
        ++interior;
        // 1e-12: rounding in differences of values up to ~5 divided by 2h = 0.5.
        EXPECT_NEAR(v->w[k], 0.0, 1e-12) << k;
      }
    EXPECT_EQ(interior, 7 * 5);
    EXPECT_NEAR(rms_vorticity(*v), 0.0, 1e-12);  // same reason
  }
  // The quadratic field's cross derivatives are not zero separately (control: the
  // check above is not trivially satisfied): du_r/dz = 2r ~ 2 at the interior.
  const DisplacementField q = sampled(
      h, 9, 7, [](double r, double z) { return 2.0 * r * z; }, [](double, double) { return 0.0; });
  const VorticityField vq = vorticity_field(q);
  const auto k = static_cast<std::size_t>(q.index(4, 3));
  EXPECT_NEAR(vq.w[k], -2.0 * 4.5 * h, 1e-12);  // -du_r/dz = -2 r at r = 4.5 h; rounding only
}

TEST(Vorticity, BoundaryCellsAreExcludedEvenWithWildValues) {
  // Rigid rotation inside, garbage on the grid boundary: interior cells next to the
  // boundary use boundary values as neighbours, so only cells at least 2 from the edge
  // keep 2 Omega; the boundary cells themselves never get a value.
  const double omega = 1.5, h = 1.0;
  DisplacementField f =
      sampled(h, 8, 8, [&](double, double z) { return -omega * z; }, [&](double r, double) { return omega * r; });
  for (int iz = 0; iz < f.nz; ++iz)
    for (int ir = 0; ir < f.nr; ++ir)
      if (on_grid_boundary(f, ir, iz)) f.ur[static_cast<std::size_t>(f.index(ir, iz))] = 1e6;
  const VorticityField v = vorticity_field(f);
  for (int iz = 0; iz < f.nz; ++iz)
    for (int ir = 0; ir < f.nr; ++ir) {
      const auto k = static_cast<std::size_t>(f.index(ir, iz));
      EXPECT_EQ(static_cast<bool>(v.interior[k]), !on_grid_boundary(f, ir, iz)) << ir << ',' << iz;
      if (ir >= 2 && iz >= 2 && ir <= 5 && iz <= 5) {
        EXPECT_NEAR(v.w[k], 2.0 * omega, 1e-12);  // rounding only
      }
    }
}

TEST(Vorticity, EmptyCellsAndTheirNeighboursAreNotInterior) {
  const double h = 1.0;
  DisplacementField f =
      sampled(h, 7, 7, [](double, double z) { return -z; }, [](double r, double) { return r; });
  const auto hole = static_cast<std::size_t>(f.index(3, 3));
  f.count[hole] = 0;
  f.ur[hole] = f.uz[hole] = std::nan("");
  const VorticityField v = vorticity_field(f);
  int interior = 0;
  for (int iz = 0; iz < f.nz; ++iz)
    for (int ir = 0; ir < f.nr; ++ir) {
      const auto k = static_cast<std::size_t>(f.index(ir, iz));
      const bool near_hole = std::abs(ir - 3) + std::abs(iz - 3) <= 1;
      EXPECT_EQ(static_cast<bool>(v.interior[k]), !on_grid_boundary(f, ir, iz) && !near_hole) << ir << ',' << iz;
      if (v.interior[k]) {
        ++interior;
        EXPECT_NEAR(v.w[k], 2.0, 1e-12);  // rounding only; no NaN leaks from the hole
      }
    }
  EXPECT_EQ(interior, 25 - 5);
  EXPECT_NEAR(rms_vorticity(v), 2.0, 1e-12);  // same reason
}

TEST(Vorticity, NoInteriorGivesNaNRms) {
  const VorticityField v = vorticity_field(
      sampled(1.0, 2, 5, [](double, double) { return 1.0; }, [](double, double) { return 1.0; }));
  for (char c : v.interior) EXPECT_FALSE(c);
  EXPECT_TRUE(std::isnan(rms_vorticity(v)));
}

TEST(Vorticity, FromParticlesOfARigidRotation) {
  // End to end: particles on a lattice around the axis displaced by a small rigid
  // rotation in each (r, z) half-plane; the polar average keeps u, so w = 2 Omega.
  const double omega = 0.01, r0 = 2.0, z0 = 2.0, h = 0.5;
  std::vector<Vec3> a, b;
  for (int iz = 0; iz < 8; ++iz)
    for (int ir = 0; ir < 8; ++ir)
      for (int j = 0; j < 6; ++j) {
        const double r = (ir + 0.5) * h, z = (iz + 0.5) * h, phi = j * M_PI / 3.0 + 0.1 * ir;
        const Vec3 er(std::cos(phi), std::sin(phi), 0.0);
        a.push_back(r * er + Vec3(0, 0, z));
        b.push_back(a.back() + (-omega * (z - z0)) * er + Vec3(0, 0, omega * (r - r0)));
      }
  const DisplacementField f = displacement_field(a, b, h, 8, 8);
  for (int c : f.count) EXPECT_EQ(c, 6);
  const VorticityField v = vorticity_field(f);
  // 1e-12: rounding of displacements ~1e-2 formed as differences of positions ~4,
  // divided by 2h = 1.
  EXPECT_NEAR(rms_vorticity(v), 2.0 * omega, 1e-12);
}

}  // namespace
}  // namespace ratchet
