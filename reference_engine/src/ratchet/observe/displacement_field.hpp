// Displacement and vorticity fields of the bed in the (r, z) plane (paper s.2 "an
// averaging around the central axis using a grid ... mapping to cylindrical
// coordinates, where an averaging over the polar angle is performed", s.3 Figs. 5-7;
// docs/output-format.md, `displacement_<a>_<b>.csv`). Pure functions of particle
// centres, no World.
#pragma once

#include <cmath>
#include <vector>

#include "ratchet/core/types.hpp"

namespace ratchet {

// Polar-angle average of the displacement on a uniform grid of square cells of side
// `cell`, starting at r = 0 and z = 0: cell (ir, iz) covers
// [ir cell, (ir+1) cell) x [iz cell, (iz+1) cell). Arrays are row-major, [iz * nr + ir].
struct DisplacementField {
  double cell = 0.0;
  int nr = 0, nz = 0;
  std::vector<double> ur, uz;  // mean radial / vertical displacement; NaN where count == 0
  std::vector<int> count;      // particles averaged in the cell
  int index(int ir, int iz) const { return iz * nr + ir; }
};

// Radial cells of the fields' grid in a container of this bottom radius: the grid
// reaches 1.5 bottom radii, room for the wall of an opened cone above the bottom (at
// 8 degrees the paper bed's top is 1.34 bottom radii wide). The cycle windows and the
// stage fields share it (run/displacement_windows.cpp, run/stage_fields.cpp).
inline int radial_cells(double bottom_radius, double cell) {
  const int n = static_cast<int>(std::ceil(1.5 * bottom_radius / cell));
  return n > 1 ? n : 1;
}

// Displacement d = positions_b[i] - positions_a[i] of each particle (same ids in both
// snapshots), in cylindrical components about the z axis at the particle's position at
// time a: u_r = d . e_r with e_r = (x, y, 0) / r, u_z = d_z; a particle on the axis
// (r < 1e-12) contributes u_r = 0. Each particle falls in cell (floor(r / cell),
// floor(z / cell)) of its position at time a; particles outside the nr x nz grid
// (z < 0, r >= nr cell or z >= nz cell) are left out.
// Throws std::invalid_argument for snapshots of different sizes, cell <= 0, nr or
// nz < 1, or non-finite positions.
DisplacementField displacement_field(const std::vector<Vec3>& positions_a, const std::vector<Vec3>& positions_b,
                                     double cell, int nr, int nz);

// The same with the cell and e_r taken at a third snapshot `reference` (same ids):
// the displacement positions_b - positions_a of each particle, binned where it was at
// `reference`. Fields of consecutive intervals binned at one reference add up cell by
// cell to the field of the whole (run/stage_fields.hpp: heating + cooling).
DisplacementField displacement_field(const std::vector<Vec3>& reference, const std::vector<Vec3>& positions_a,
                                     const std::vector<Vec3>& positions_b, double cell, int nr, int nz);

// A field from per-cell values given directly (row-major [iz * nr + ir]), e.g. an
// analytic field sampled at cell centres ((ir + 1/2) cell, (iz + 1/2) cell) for tests.
// Throws std::invalid_argument if an array's size is not nr * nz, cell <= 0, nr or
// nz < 1, or a count is negative.
DisplacementField field_from_values(double cell, int nr, int nz, std::vector<double> ur, std::vector<double> uz,
                                    std::vector<int> count);

// Vorticity w = du_z/dr - du_r/dz (the paper's curl of u = (u_r, u_z), s.3). The
// paper uses "the scheme proposed in Sumesh 2013" (its reference list is not in our
// copy of the paper); what is implemented here is plain second-order central
// differences on the uniform grid:
//   w = (u_z[ir+1] - u_z[ir-1]) / (2 cell) - (u_r[iz+1] - u_r[iz-1]) / (2 cell).
// Only INTERIOR cells get a value: cells not on the grid boundary, populated, and with
// all 4 neighbours populated ("to remove boundary effects ... all boundary cells are
// neglected"). Elsewhere w is NaN and interior is 0. Exact for fields linear or
// quadratic in (r, z).
struct VorticityField {
  std::vector<double> w;       // row-major [iz * nr + ir], NaN outside the interior
  std::vector<char> interior;  // 1 for interior cells
};

VorticityField vorticity_field(const DisplacementField& field);

// Root mean square of w over the interior cells, W_rms (paper s.3, Fig. 8); NaN if
// there is no interior cell.
double rms_vorticity(const VorticityField& vorticity);

}  // namespace ratchet
