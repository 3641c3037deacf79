"""Convection cells counted in a run's stage fields: the paper's closing question, whether
a larger bed forms more vortices than the one toroidal cell of its Fig. 6.

A toroidal cell turns one way: the vorticity w = du_z/dr - du_r/dz (fields.vorticity)
has one sign over it. Cells side by side in r turn opposite ways, so the vorticity
changes sign from one to the next. Per radial column of cells the circulation
C(r) = sum over z of w h^2 (interior cells only); a *band* is a maximal run of columns of
one sign of C, and its circulation the sum of its columns. The bands of a field, with
each one's share of the field's absolute circulation (sum of |band|), say how many
counter-rotating regions it has and how strong each is; fields.circulation's coherence
is the same information for the whole bed in one number. Beside it, the grain-weighted
mean vertical displacement of each column, u_z(r): one cell rising at the axis and
sinking at the wall changes its sign once; where it does (uz_edge), the width of the band
along the wall (wall_band) and the middle's mean u_z per cycle (uz_middle) say how much of
the bed the cell takes and how fast its middle moves.

What counts as a cell is a threshold on the band's share (CELL_SHARE below); its reason
is measured, not assumed: single-cycle fields of the paper bed, which has one cell
(docs/paper-reproduction.md, Fig. 6), split off minority bands by noise, and the share
those reach is the noise floor a second cell must clear.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import fields

#: A band is a cell when it holds at least this share of the field's absolute
#: circulation. Reason: in the 100 single-cycle fields of the five paper-tier runs at
#: 0 deg, ratio 10 (validation/results/paper/theta0_ratio10, 2000 polyhedra, one cell),
#: the second-strongest band held at most 0.28 in 99 of them (0.46 once: cycle 7 of seed
#: 4, whose absolute circulation is a sixth of its first cycle's); in their first cycles,
#: the strongest, none had a second band at all. 0.3 is above what noise made in 99 of the
#: 100.
CELL_SHARE = 0.3

#: The middle of the bed, r/R below this, whose mean u_z says how fast it moves as a
#: whole: the inner half, where the paper bed's one cell rises (its u_z changes sign at
#: r/R = 0.57-0.61 in the first cycle).
MIDDLE = 0.5


@dataclass
class Band:
    r_from: float          # inner edge of its first column
    r_to: float            # outer edge of its last column
    circulation: float     # sum of w h^2 over its columns' interior cells
    share: float           # |circulation| / the field's sum of |band circulation|

    @property
    def sense(self) -> str:
        return "rising at the wall" if self.circulation > 0 else "sinking at the wall"

    def to_dict(self) -> dict:
        return {"r_from": self.r_from, "r_to": self.r_to, "circulation": self.circulation,
                "share": self.share, "sense": self.sense}


@dataclass
class CellCount:
    cycles: list[int]
    radius: float                       # the bed's radius and height (fields.bed_extent)
    height: float
    interior_cells: int
    coherence: float                    # fields.circulation's: +-1 for one sense throughout
    bands: list[Band] = field(default_factory=list)
    column_circulation: list[float] = field(default_factory=list)  # C(r), NaN without interior cells
    uz_profile: list[float] = field(default_factory=list)          # grain-weighted u_z per column
    r: list[float] = field(default_factory=list)                   # the columns' centres

    @property
    def cells(self) -> int:
        """Bands holding at least CELL_SHARE of the absolute circulation."""
        return sum(1 for b in self.bands if b.share >= CELL_SHARE)

    def _signed_profile(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The columns with a sign (finite, non-zero u_z): their r, u_z, and the indices i
        where u_z changes sign between the i-th and the next."""
        r, uz = np.array(self.r), np.array(self.uz_profile)
        ok = np.isfinite(uz) & (uz != 0.0)
        r, uz = r[ok], uz[ok]
        return r, uz, np.flatnonzero(np.sign(uz[:-1]) != np.sign(uz[1:]))

    @property
    def uz_sign_changes(self) -> int:
        return int(self._signed_profile()[2].size)

    @property
    def uz_middle(self) -> float:
        """The mean of u_z(r) over the columns of r/R < MIDDLE, per cycle: how fast the
        middle rises (or sinks) as a whole; NaN without such columns."""
        r, uz = np.array(self.r), np.array(self.uz_profile)
        pick = np.isfinite(uz) & (r < MIDDLE * self.radius)
        return float(np.mean(uz[pick])) / len(self.cycles) if pick.any() else math.nan

    @property
    def uz_edge(self) -> float:
        """r/R where u_z(r) changes sign for the last time going out (linear between the
        columns' centres): where the wall's band of one sense begins; NaN without a change."""
        r, uz, change = self._signed_profile()
        if not change.size:
            return math.nan
        i = change[-1]
        return float(r[i] + (r[i + 1] - r[i]) * uz[i] / (uz[i] - uz[i + 1])) / self.radius

    @property
    def wall_band(self) -> float:
        """The width of that band along the wall, R (1 - uz_edge), in the fields' length."""
        return self.radius * (1.0 - self.uz_edge)

    def to_dict(self) -> dict:
        return {"cycles": self.cycles, "radius": self.radius, "height": self.height,
                "interior_cells": self.interior_cells, "coherence": self.coherence,
                "cells": self.cells, "cell_share": CELL_SHARE, "uz_sign_changes": self.uz_sign_changes,
                "uz_middle": self.uz_middle, "uz_edge": self.uz_edge, "wall_band": self.wall_band,
                "bands": [b.to_dict() for b in self.bands], "r": self.r,
                "column_circulation": self.column_circulation, "uz_profile": self.uz_profile}


def bands_of(columns: np.ndarray, cell: float) -> list[Band]:
    """The bands of the column circulations (NaN: a column without interior cells, skipped;
    an exact zero joins no band)."""
    runs: list[list] = []  # [sign, first column, last column, sum]
    for i, c in enumerate(columns):
        if not math.isfinite(c) or c == 0.0:
            continue
        s = math.copysign(1.0, c)
        if runs and runs[-1][0] == s:
            runs[-1][2] = i
            runs[-1][3] += float(c)
        else:
            runs.append([s, i, i, float(c)])
    total = sum(abs(r[3]) for r in runs)
    return [Band(r_from=first * cell, r_to=(last + 1) * cell, circulation=value,
                 share=abs(value) / total if total > 0 else math.nan)
            for _, first, last, value in runs]


def count_cells(f: fields.StageFields, cycles) -> CellCount:
    """The bands and the u_z profile of the field summed over `cycles` (heating plus
    cooling, fields.StageFields.cumulative)."""
    cycles = [int(c) for c in cycles]
    ur, uz, populated = f.cumulative(cycles)
    w = fields.vorticity(ur, uz, f.cell)
    interior = np.isfinite(w)
    area = f.cell ** 2
    columns = np.where(interior.any(axis=0), np.nansum(w, axis=0) * area, np.nan)
    pick = np.isin(f.cycles, cycles)
    grains = f.count[pick].sum(axis=0)  # grains per cell over the cycles: the weights of u_z
    weight = np.where(populated, grains, 0)
    total = weight.sum(axis=0)
    uz_profile = np.where(total > 0, np.nansum(np.nan_to_num(uz) * weight, axis=0) / np.maximum(total, 1), np.nan)
    total_abs = float(np.sum(np.abs(w[interior])))
    coherence = float(np.sum(w[interior])) / total_abs if total_abs > 0 else math.nan  # fields.circulation's
    radius, height = fields.bed_extent(f)
    return CellCount(cycles=cycles, radius=radius, height=height, interior_cells=int(interior.sum()),
                     coherence=coherence, bands=bands_of(columns, f.cell),
                     column_circulation=[float(c) for c in columns], uz_profile=[float(u) for u in uz_profile],
                     r=[float(x) for x in f.r])
