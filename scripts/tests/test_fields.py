"""Tests of scripts/analysis/fields.py (Fig. 5, Fig. 6 and the steady state) on synthetic
stage fields and cycles: fields with the paper's behaviour pass; for each check a field
against it is contradicted at a reduced tier and failed at the paper tier, and one within
its uncertainty is not resolved (docs/trends.md "States").

Run with Debian's interpreter: /usr/bin/python3 -m pytest -q scripts/tests/test_fields.py
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

SCRIPTS = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(SCRIPTS))

from analysis import fields, inputs, plots, trends  # noqa: E402
from paper_runs import STAGE_ROWS, volume_rows  # noqa: E402

NR, NZ, CELL = 8, 10, 1.0
R, H = NR * CELL, NZ * CELL
ALPHA_P = 1e-4


def slump(r, z, a=0.1):
    """Heating: outward and downward, vanishing at the bottom of the axis."""
    return a * (r / R) * (0.5 + z / H), -a * (z / H) * (0.5 + r / R)


def vortex(r, z, c, cells=1):
    """u = (d psi/dz, -d psi/dr), psi = c sin(pi r/R) sin(cells pi z/H): w = -lap psi; one
    cell: of the sign of c everywhere (c > 0: rising at the wall); two: two cells stacked,
    turning opposite ways (no dominant sense)."""
    m = cells * math.pi / H
    return (c * m * np.sin(math.pi * r / R) * np.cos(m * z),
            -c * math.pi / R * np.cos(math.pi * r / R) * np.sin(m * z))


def write_stage_fields(folder: Path, cycles=6, heating=slump, circulation=0.2, noise=0.002,
                       seed=0, uniform=False, cells=1):
    """stage_fields.csv: the heating field, and a cooling that takes back 90 % of it and
    adds a vortex (`cells` stacked); `uniform` makes every grain sink by the same amount on
    heating and rise on cooling (no still zone)."""
    rng = np.random.default_rng(seed)
    folder.mkdir(parents=True, exist_ok=True)
    iz, ir = np.meshgrid(np.arange(NZ), np.arange(NR), indexing="ij")
    r, z = (ir + 0.5) * CELL, (iz + 0.5) * CELL
    rows = []
    for k in range(cycles):
        hr, hz = heating(r, z)
        if uniform:
            hr, hz = np.full_like(r, 0.05), np.full_like(r, -0.05)
        vr, vz = vortex(r, z, circulation, cells)
        cr, cz = -0.9 * hr + vr, -0.9 * hz + vz
        frame = pd.DataFrame({"cycle": k, "ir": ir.ravel(), "iz": iz.ravel(), "r": r.ravel(),
                              "z": z.ravel(), "count": 5})
        for name, v in (("ur_heating", hr), ("uz_heating", hz), ("ur_cooling", cr), ("uz_cooling", cz)):
            frame[name] = v.ravel() + noise * rng.normal(size=v.size)
        rows.append(frame)
    pd.concat(rows).to_csv(folder / fields.STAGE_FILE, index=False, float_format="%.6g")


def write_cycles(folder: Path, cycles=10, steady_from=3, p=10.0, v_low=0.97, dilation=0.005, swing=0.04,
                 seed=0, series="volume.csv", start=0.3, compaction=None):
    """cycles.csv: peaks going from start x p to p by cycle steady_from (rising for start
    < 1, falling above) and flat after it (within 1 %);
    and the V/V0 series (volume_rows) as `series` (volume.csv or timeseries.csv; None:
    none), whose ends of heating and cooling cycles.csv repeats. compaction: V/V0 at the
    ends of cooling falls instead by that much, linearly up to cycle steady_from and then
    flat (within 1e-5), in cycles.csv only."""
    rng = np.random.default_rng(seed)
    folder.mkdir(parents=True, exist_ok=True)
    k = np.arange(cycles)
    peak = np.where(k < steady_from, p * (start + (1 - start) * k / max(steady_from, 1)), p)
    peak = peak * (1 + 0.005 * rng.normal(size=cycles))
    rows = volume_rows(cycles, v_low, dilation, swing, seed=seed)
    per_cycle = sum(STAGE_ROWS)
    ends = 1 + per_cycle * k
    pd.DataFrame({"cycle": k, "peak_pressure": peak, "t_peak": k + 0.5,
                  "V_over_V0_end_heating": rows["V_over_V0"].to_numpy()[ends + STAGE_ROWS[0] - 1],
                  "V_over_V0_end_cooling": rows["V_over_V0"].to_numpy()[ends + sum(STAGE_ROWS[:3]) - 1]}).to_csv(
        folder / "cycles.csv", index=False)
    if compaction is not None:
        frame = pd.read_csv(folder / "cycles.csv")
        frame["V_over_V0_end_cooling"] = (v_low - compaction * np.minimum(k, steady_from) / max(steady_from, 1)
                                          + 1e-5 * rng.normal(size=cycles))
        frame.to_csv(folder / "cycles.csv", index=False)
    if series is not None:
        rows.to_csv(folder / series, index=False)


def build(folder: Path, kind: str, values, realizations=3, cycles=10, stage=None, run=None) -> Path:
    """A sweep folder: summary.csv and runs/<run>/ with stage_fields.csv and cycles.csv.
    stage(value, s) and run(value, s) give keyword arguments of write_stage_fields and
    write_cycles (None: no stage fields)."""
    rows, n = [], 0
    for x in values:
        for s in range(realizations):
            row = {"run": n, "seed": 1 + s, "thermal.alpha_p": ALPHA_P, "P_max": 1.0, "status": "completed"}
            if kind == "angle":
                row["container.opening_angle_deg"] = x
            else:
                row["thermal.alpha_c"] = x * ALPHA_P
            rows.append(row)
            folder_run = folder / "runs" / str(n)
            kwargs = {} if stage is None else stage(x, s)
            if kwargs is not None:
                write_stage_fields(folder_run, seed=n, **kwargs)
            write_cycles(folder_run, cycles=cycles, seed=n, **({} if run is None else run(x, s)))
            n += 1
    folder.mkdir(parents=True, exist_ok=True)
    pd.DataFrame(rows).to_csv(folder / "summary.csv", index=False)
    return folder


def results(folder: Path, kind: str, tier="paper") -> dict[str, list]:
    a = trends.analyse(inputs.load_sweep(folder), kind, tier)
    out: dict[str, list] = {}
    for r in a.results:
        if r.check_id in fields.CHECK_IDS:
            out.setdefault(r.check_id, []).append(r)
    return out


def statuses(found, check_id):
    return [r.status for r in found.get(check_id, [])]


# --------------------------------------------------------------------------- reading


def test_stage_fields_are_read_on_their_grid(tmp_path):
    write_stage_fields(tmp_path, cycles=3, noise=0.0)
    f = fields.read_stage_fields(tmp_path)
    assert f.cell == pytest.approx(CELL)
    assert list(f.cycles) == [0, 1, 2] and f.count.shape == (3, NZ, NR)
    ur, uz = slump(f.r[3], f.z[7])
    assert f.ur_heating[1, 7, 3] == pytest.approx(ur, rel=1e-5)
    assert f.uz_heating[1, 7, 3] == pytest.approx(uz, rel=1e-5)
    assert fields.read_stage_fields(tmp_path / "none") is None


def test_a_file_against_the_format_is_an_error_naming_file_and_column(tmp_path):
    write_stage_fields(tmp_path, cycles=2)
    frame = pd.read_csv(tmp_path / fields.STAGE_FILE)
    frame.drop(columns=["uz_cooling"]).to_csv(tmp_path / fields.STAGE_FILE, index=False)
    with pytest.raises(fields.FieldsError, match=r"stage_fields\.csv: missing column\(s\) uz_cooling"):
        fields.read_stage_fields(tmp_path)
    frame["count"] = -1
    frame.to_csv(tmp_path / fields.STAGE_FILE, index=False)
    with pytest.raises(fields.FieldsError, match=r"stage_fields\.csv: column 'count': expected integers"):
        fields.read_stage_fields(tmp_path)


def test_the_cumulative_field_circulates_with_the_vortex_sign(tmp_path):
    for c, sense in ((0.3, "rising at the wall"), (-0.3, "sinking at the wall")):
        write_stage_fields(tmp_path, circulation=c, noise=0.0)
        circ = fields.circulation(fields.read_stage_fields(tmp_path))
        assert circ.sense == sense
        assert abs(circ.coherence) > 0.8
        assert circ.cells == (NR - 2) * (NZ - 2)


def test_vorticity_follows_the_engine_rule():
    # A rigid rotation u = Omega (-(z - z0), r - r0) has w = 2 Omega on interior cells only.
    z, r = np.meshgrid((np.arange(5) + 0.5), (np.arange(4) + 0.5), indexing="ij")
    ur, uz = -0.01 * (z - 2.0), 0.01 * (r - 2.0)
    ur[2, 2] = np.nan  # an empty cell: itself and its neighbours are not interior
    w = fields.vorticity(ur, uz, 1.0)
    assert np.isnan(w[0]).all() and np.isnan(w[:, 0]).all() and np.isnan(w[2, 2])
    assert np.isnan(w[1, 2]) and np.isnan(w[3, 2])
    assert w[1, 1] == pytest.approx(0.02)


def test_cycles_to_steady_is_the_first_cycle_in_the_band():
    peaks = [1.0, 4.0, 8.0, 9.9, 10.0, 10.1, 9.95, 10.05, 10.0, 9.9]
    got = fields.cycles_to_steady(pd.DataFrame({"cycle": range(10), "peak_pressure": peaks}))
    # Steady half: cycles 5-9, mean 10.0, sigma 0.079 -> band max(0.16, 0.5) = 0.5.
    assert got["mean"] == pytest.approx(10.0) and got["band"] == pytest.approx(0.5)
    assert got["cycle"] == 3
    assert math.isnan(fields.cycles_to_steady(pd.DataFrame({"cycle": [0], "peak_pressure": [1.0]}))["cycle"])


def test_the_stages_of_a_series_are_told_by_its_temperature():
    rows = volume_rows(cycles=3)
    cycle, ramps = fields.thermal_stages(rows["T"].to_numpy())
    heat, hot, cool, cold = STAGE_ROWS
    assert cycle[0] == -1 and cycle[1] == 0 and cycle[-1] == 2  # the row before heating: no cycle
    assert len(ramps) == 3
    # A ramp's rows lie strictly between T0 and T1: the last sample at T0 is the hold's.
    assert [len(r) for r in ramps] == [cool - 1] * 3
    assert ramps[1][0] == 1 + sum(STAGE_ROWS) + heat + hot


def test_peak_density_and_dilation_are_read_off_the_volume_series(tmp_path):
    write_cycles(tmp_path, cycles=10, v_low=0.95, dilation=0.006, swing=0.05)
    series, source = inputs.read_volume_series(tmp_path)
    assert source == "volume.csv"
    v = fields.peak_density(series)
    d = fields.cooling_dilation(series)
    assert v.value == pytest.approx(0.95, abs=0.001) and v.n == 5 and 0 < v.se < 0.001
    assert d.value == pytest.approx(0.006, abs=0.001) and d.n == 5 and d.source == "cycles"
    # The end of cooling is lifted by the dilation: it is not the peak density.
    cycles = inputs.read_cycles(tmp_path)
    assert cycles["V_over_V0_end_cooling"].iloc[5:].mean() > v.value + 0.005


def test_the_containers_contraction_alone_is_no_dilation(tmp_path):
    # V/V0 falls by 0.08 over each cooling and never rises in it: no dilation, though the
    # swing between the ends of heating and cooling (the measure of 2026-11-27) is 0.08.
    write_cycles(tmp_path, cycles=10, dilation=0.0, swing=0.08)
    series, _ = inputs.read_volume_series(tmp_path)
    assert fields.cooling_dilation(series).value == 0.0
    cycles = inputs.read_cycles(tmp_path)
    swing = (cycles["V_over_V0_end_heating"] - cycles["V_over_V0_end_cooling"]).iloc[5:].mean()
    assert swing == pytest.approx(0.08, abs=0.002)


def test_the_series_comes_from_volume_csv_else_timeseries_csv(tmp_path):
    write_cycles(tmp_path / "ts", series="timeseries.csv")
    assert inputs.read_volume_series(tmp_path / "ts")[1] == "timeseries.csv"
    write_cycles(tmp_path / "none", series=None)
    frame, why = inputs.read_volume_series(tmp_path / "none")
    assert frame is None and why.startswith("no volume.csv or timeseries.csv")
    (tmp_path / "bare").mkdir()
    pd.DataFrame({"t": [0.0, 1.0], "pressure": [0.0, 1.0]}).to_csv(tmp_path / "bare" / "timeseries.csv", index=False)
    frame, why = inputs.read_volume_series(tmp_path / "bare")
    assert frame is None and "outputs.volume" in why
    assert math.isnan(fields.peak_density(None).value) and math.isnan(fields.cooling_dilation(None).value)


# --------------------------------------------------------------------------- checks


def test_the_papers_fields_pass_every_field_check(tmp_path):
    found = results(build(tmp_path / "a", "angle", (0.0, 4.0, 8.0)), "angle")
    # Fig. 5 is the paper's at 0 deg (and ratio 10) only; the cell of Fig. 6 at every point.
    for check_id in ("stage_heating_direction", "stage_cooling_direction", "still_zone"):
        assert statuses(found, check_id) == ["passed", "skipped", "skipped"], [
            (r.check, r.status, r.tolerance) for r in found[check_id]]
    assert statuses(found, "toroidal_cell") == ["passed"] * 3
    assert "rising at the wall" in found["toroidal_cell"][0].tolerance


def assert_against(found_by_tier: dict, check_id: str, count: int = 1):
    """The same data at a reduced tier and at the paper tier: contradicted, then failed."""
    quick = found_by_tier["quick"][check_id]
    assert [r.status for r in quick] == ["contradicted"] * count, [(r.check, r.reason) for r in quick]
    for r in quick:
        line = r.record()
        assert line["passed"] is False and line["resolved"] is True and line["contradicted"] is True
        assert r.reason.startswith("contradicted at this scale (reduced): ")
        assert f"[{r.detail['tier']} tier: " in r.reason
    paper = found_by_tier["paper"][check_id]
    assert [r.status for r in paper] == ["failed"] * count, [(r.check, r.reason) for r in paper]
    assert paper[0].reason.startswith("failed: ") and "contradicted" not in paper[0].record()


def by_tier(folder: Path, kind: str, tiers=("quick", "paper")) -> dict:
    return {tier: results(folder, kind, tier) for tier in tiers}


def test_inward_motion_on_heating_is_contradicted_below_the_paper_tier_and_fails_at_it(tmp_path):
    def inward(r, z):
        ur, uz = slump(r, z)
        return -ur, uz
    found = by_tier(build(tmp_path / "a", "angle", (0.0,), stage=lambda x, s: {"heating": inward}),
                    "angle")
    assert_against(found, "stage_heating_direction")
    assert "u_r resolved inward on heating" in found["quick"]["stage_heating_direction"][0].reason
    # The cooling takes back 90 % of it: outward on cooling, against the paper too.
    assert_against(found, "stage_cooling_direction")


def test_fig5_at_another_point_is_not_the_papers_statement(tmp_path):
    # alpha_c = alpha_p: the container grows with the grains and heating lifts the bed;
    # the paper states Fig. 5 for alpha_c/alpha_p = 10 only, so ratio 1 is skipped with its
    # measurement, never contradicted, while ratio 10 with the same field is.
    def rising(r, z):
        ur, uz = slump(r, z)
        return ur, -uz
    found = results(build(tmp_path / "a", "ratio", (1.0, 10.0), stage=lambda x, s: {"heating": rising}),
                    "ratio", "quick")
    first, second = found["stage_heating_direction"]
    assert (first.status, second.status) == ("skipped", "contradicted")
    assert "alpha_c/alpha_p = 10 only (Fig. 5)" in first.reason
    assert "measured here, not a check: u_r" in first.reason
    assert found["still_zone"][0].status == "skipped" and found["still_zone"][1].status != "skipped"


def test_downward_on_cooling_on_a_quick_bed_is_contradicted_at_its_scale(tmp_path):
    # One realization of 3 cycles, as the quick tier: the interval is over its cycles
    # (2 dof, k = 4.3); a bed rising on heating sinks on cooling, beyond it.
    def rising(r, z):
        ur, uz = slump(r, z)
        return ur, -uz
    folder = build(tmp_path / "a", "angle", (0.0,), realizations=1, cycles=3,
                   stage=lambda x, s: {"heating": rising, "cycles": 3})
    found = by_tier(folder, "angle")
    assert_against(found, "stage_cooling_direction")
    result = found["quick"]["stage_cooling_direction"][0]
    assert "u_z resolved downward on cooling" in result.reason
    assert "quick tier's beds" in result.reason
    assert result.detail["uz"]["source"] == "cycles" and result.detail["uz"]["dof"] == 2


def test_a_direction_within_the_noise_is_not_resolved(tmp_path):
    def faint(r, z):
        return slump(r, z, a=1e-4)
    found = results(build(tmp_path / "a", "angle", (0.0,), realizations=1,
                          stage=lambda x, s: {"heating": faint, "noise": 0.01}), "angle")
    assert statuses(found, "stage_heating_direction") == ["unresolved"]
    result = found["stage_heating_direction"][0]
    assert result.reason.startswith("not resolved at this scale: ")
    assert result.record()["passed"] is True and result.record()["resolved"] is False


def test_one_cycle_of_one_run_is_not_resolved(tmp_path):
    found = results(build(tmp_path / "a", "angle", (0.0,), realizations=1,
                          stage=lambda x, s: {"cycles": 1}), "angle")
    for check_id in ("stage_heating_direction", "still_zone"):
        assert statuses(found, check_id) == ["unresolved"], check_id


def test_a_bed_moving_as_a_whole_has_no_still_zone(tmp_path):
    folder = build(tmp_path / "a", "angle", (0.0,),
                   stage=lambda x, s: {"uniform": True, "circulation": 0.0})
    found = by_tier(folder, "angle")
    assert_against(found, "still_zone")
    assert found["paper"]["still_zone"][0].measured == pytest.approx(1.0, abs=0.1)


def test_a_still_zone_within_the_scatter_is_not_resolved(tmp_path):
    # Two cycles of one bed (1 dof, k = 12.7) whose bottom moves a third as much as the rest.
    def third(r, z):
        ur, uz = slump(r, z)
        scale = np.where((r < R / 3) & (z < H / 4), 0.3, 1.0)
        return ur * 0 + 0.05 * scale, uz * 0 - 0.05 * scale
    folder = build(tmp_path / "a", "angle", (0.0,), realizations=1,
                   stage=lambda x, s: {"heating": third, "cycles": 2, "noise": 0.01, "circulation": 0.0})
    found = results(folder, "angle", "quick")
    assert statuses(found, "still_zone") == ["unresolved"], found["still_zone"][0].reason
    assert "holds 0.3" in found["still_zone"][0].reason


def test_a_grid_coarser_than_the_still_zone_cannot_contradict_it(tmp_path):
    folder = build(tmp_path / "a", "angle", (0.0, 4.0),
                   stage=lambda x, s: {"uniform": True, "circulation": 0.0})
    for run in (folder / "runs").iterdir():  # two rows of cells: no cell centre below H/4
        frame = pd.read_csv(run / fields.STAGE_FILE)
        frame[frame["iz"] < 2].to_csv(run / fields.STAGE_FILE, index=False)
    found = results(folder, "angle", "paper")
    assert statuses(found, "still_zone") == ["unresolved", "skipped"]
    assert "coarser than the zone" in found["still_zone"][0].reason
    assert found["still_zone"][0].detail["coarse_region"] is True


def test_opposite_circulation_in_one_realization_is_not_resolved(tmp_path):
    def stage(x, s):
        return {"circulation": -0.2 if (x == 4.0 and s == 1) else 0.2}
    found = results(build(tmp_path / "a", "angle", (0.0, 4.0), stage=stage), "angle")
    assert statuses(found, "toroidal_cell") == ["passed", "unresolved"]
    assert "mixed" in found["toroidal_cell"][1].tolerance
    assert "turn opposite ways" in found["toroidal_cell"][1].reason


def test_two_counter_rotating_cells_are_no_dominant_cell(tmp_path):
    folder = build(tmp_path / "a", "angle", (0.0,), realizations=4,
                   stage=lambda x, s: {"circulation": 0.2, "cells": 2,
                                       "heating": lambda r, z: (0 * r, 0 * z)})
    found = by_tier(folder, "angle")
    assert_against(found, "toroidal_cell")
    assert "no dominant cell" in found["quick"]["toroidal_cell"][0].reason


def test_one_realization_never_contradicts_the_cell(tmp_path):
    folder = build(tmp_path / "a", "angle", (0.0,), realizations=1,
                   stage=lambda x, s: {"circulation": 0.2, "cells": 2,
                                       "heating": lambda r, z: (0 * r, 0 * z)})
    assert statuses(results(folder, "angle", "paper"), "toroidal_cell") == ["unresolved"]
    single = build(tmp_path / "b", "angle", (0.0,), realizations=1)
    assert statuses(results(single, "angle", "quick"), "toroidal_cell") == ["passed"]


def test_steady_state_sooner_at_larger_angles_passes_and_later_is_against(tmp_path):
    sooner = build(tmp_path / "s", "angle", (0.0, 4.0, 8.0),
                   run=lambda x, s: {"steady_from": int(6 - 0.5 * x)})
    later = build(tmp_path / "l", "angle", (0.0, 4.0, 8.0),
                  run=lambda x, s: {"steady_from": int(2 + 0.5 * x)})
    assert statuses(results(sooner, "angle"), "steady_time_theta") == ["passed"]
    assert_against(by_tier(later, "angle"), "steady_time_theta")


def test_steady_time_within_the_scatter_is_not_resolved(tmp_path):
    folder = build(tmp_path / "n", "angle", (0.0, 8.0), realizations=2,
                   run=lambda x, s: {"steady_from": (2, 5)[s]})
    assert statuses(results(folder, "angle"), "steady_time_theta") == ["unresolved"]


def test_peaks_rising_in_the_first_cycles_pass_and_falling_ones_are_against(tmp_path):
    # Fig. 3a / 3c: "in the first regime ... the pressure increases", for all parameters.
    def run(x, s):
        return {"start": 1.3, "steady_from": 8} if x == 1.0 else {}
    folder = build(tmp_path / "r", "ratio", (1.0, 10.0), run=run)
    found = {r.check: r for r in results(folder, "ratio")["pmax_rise"]}
    rising = found["P_max rises in the first cycles (alpha_c/alpha_p=10)"]
    assert rising.status == "passed", rising.reason
    assert rising.measured == pytest.approx(0.7, abs=0.02)   # the first peak is 0.3 of the steady one
    falling = found["P_max rises in the first cycles (alpha_c/alpha_p=1)"]
    assert falling.measured < 0 and "the peaks fall into their steady state" in falling.reason
    only_falling = build(tmp_path / "f", "ratio", (1.0,), run=run)
    assert_against(by_tier(only_falling, "ratio"), "pmax_rise")
    angle = results(build(tmp_path / "a", "angle", (0.0, 6.0)), "angle")
    assert statuses(angle, "pmax_rise") == ["passed", "passed"]   # a check of both studies


def test_a_rise_within_the_scatter_or_of_one_bed_is_not_resolved(tmp_path):
    mixed = build(tmp_path / "m", "angle", (0.0,), run=lambda x, s: {"start": (0.7, 1.2, 0.9)[s]})
    found = results(mixed, "angle")["pmax_rise"][0]
    assert found.status == "unresolved" and "holds 0" in found.reason, found.reason
    one = build(tmp_path / "o", "angle", (0.0,), realizations=1)
    found = results(one, "angle")["pmax_rise"][0]
    assert found.status == "unresolved" and "no scatter estimate" in found.reason
    short = build(tmp_path / "s", "angle", (0.0,), cycles=2)
    assert statuses(results(short, "angle"), "pmax_rise") == ["skipped"]


def test_peaks_that_rise_as_the_bed_compacts_pass_and_peaks_that_fall_are_against(tmp_path):
    # Fig. 3a / 3c: "the first regime is due to compaction [...] since pressure increases as
    # the total packing density increases". Both change up to cycle 5 of 10, then hold.
    def run(x, s):
        return {"compaction": 0.03, "steady_from": 5, "start": 1.3 if x == 1.0 else 0.3}
    folder = build(tmp_path / "r", "ratio", (1.0, 10.0), run=run)
    found = {r.check: r for r in results(folder, "ratio")["pmax_follows_density"]}
    rising = found["P_max rises with the packing density (alpha_c/alpha_p=10)"]
    assert rising.status == "passed" and rising.measured > 0.3, rising.reason
    falling = found["P_max rises with the packing density (alpha_c/alpha_p=1)"]
    assert falling.measured < -0.3 and "the peak pressure falls as the bed's density rises" in falling.reason
    assert falling.detail["compaction"] == pytest.approx([0.03] * 3, abs=1e-4)
    assert_against(by_tier(build(tmp_path / "f", "ratio", (1.0,), run=run), "ratio"), "pmax_follows_density")
    angle = results(build(tmp_path / "a", "angle", (0.0,), run=run), "angle")
    assert statuses(angle, "pmax_follows_density") == ["passed"]   # a check of both studies


def test_density_and_peaks_of_one_bed_unchanged_or_few_cycles_do_not_resolve(tmp_path):
    one = build(tmp_path / "o", "angle", (0.0,), realizations=1, run=lambda x, s: {"compaction": 0.03})
    found = results(one, "angle")["pmax_follows_density"][0]
    assert found.status == "unresolved" and "no scatter estimate" in found.reason
    # The first two beds' densities rise with their peaks, the third's fall: rho +1, +1, -1,
    # whose 95 % interval (2 dof, k = 4.3) holds 0.
    mixed = build(tmp_path / "m", "angle", (0.0,),
                  run=lambda x, s: {"compaction": (0.03, 0.03, -0.03)[s], "steady_from": 9})
    found = results(mixed, "angle")["pmax_follows_density"][0]
    assert found.status == "unresolved" and "holds 0" in found.reason, found.reason
    short = build(tmp_path / "s", "angle", (0.0,), cycles=5, run=lambda x, s: {"compaction": 0.03})
    assert statuses(results(short, "angle"), "pmax_follows_density") == ["skipped"]
    # volume_rows' V/V0 at the ends of cooling is the same in every cycle (up to its noise):
    # no compaction here, but its noise still ranks; a series that is exactly flat is left out.
    flat = build(tmp_path / "n", "angle", (0.0,), run=lambda x, s: {"compaction": 0.0})
    for run_folder in (flat / "runs").iterdir():
        frame = pd.read_csv(run_folder / "cycles.csv")
        frame["V_over_V0_end_cooling"] = 0.97
        frame.to_csv(run_folder / "cycles.csv", index=False)
    found = results(flat, "angle")["pmax_follows_density"][0]
    assert found.status == "skipped" and "3 run(s) whose peaks or densities do not change" in found.reason


def test_a_rise_whose_length_depends_on_the_ratio_passes_either_way_and_none_is_against(tmp_path):
    # Fig. 3c: the ratio sets the time scale of the rise; the paper gives no direction.
    longer = build(tmp_path / "l", "ratio", (1.0, 5.0, 10.0), run=lambda x, s: {"steady_from": int(1 + 0.5 * x)})
    shorter = build(tmp_path / "s", "ratio", (1.0, 5.0, 10.0), run=lambda x, s: {"steady_from": int(7 - 0.5 * x)})
    same = build(tmp_path / "n", "ratio", (1.0, 5.0, 10.0), run=lambda x, s: {"steady_from": 4})
    found = results(longer, "ratio")["steady_time_ratio"]
    assert [r.status for r in found] == ["passed"] and "lengthens" in found[0].reason
    found = results(shorter, "ratio")["steady_time_ratio"]
    assert [r.status for r in found] == ["passed"] and "shortens" in found[0].reason
    assert_against(by_tier(same, "ratio"), "steady_time_ratio")
    assert "no time scale set by" in results(same, "ratio")["steady_time_ratio"][0].reason
    assert "steady_time_ratio" not in results(build(tmp_path / "a", "angle", (0.0, 8.0)), "angle")


def test_peaks_that_fall_into_the_steady_state_have_no_rise_to_time(tmp_path):
    # The paper's ratio-1 beds: the peaks relax from above; their time to the band is no
    # time scale of a rise, and counting it would pass the check on a fall.
    def run(x, s):
        return {"steady_from": 8, "start": 1.3} if x == 1.0 else {"steady_from": 3}
    folder = build(tmp_path / "f", "ratio", (1.0, 5.0, 10.0), run=run)
    found = results(folder, "ratio")["steady_time_ratio"][0]
    assert found.status != "passed", found.reason   # 5 and 10 rise alike: no dependence left
    assert "3 run(s) whose peaks do not rise into the steady state" in found.reason
    only = build(tmp_path / "o", "ratio", (1.0, 10.0), run=run)
    found = results(only, "ratio")["steady_time_ratio"][0]
    assert found.status == "skipped" and "do not rise" in found.reason


def test_a_rise_length_within_the_scatter_is_not_resolved(tmp_path):
    folder = build(tmp_path / "n", "ratio", (1.0, 10.0), realizations=2,
                   run=lambda x, s: {"steady_from": (2, 5)[s]})
    found = results(folder, "ratio")["steady_time_ratio"][0]
    assert found.status == "unresolved", found.reason
    assert found.detail["allowed_change"] > 0.25 * 3.5  # the mean time is 3.5 cycles


def test_the_same_steady_density_passes_and_a_trend_is_against(tmp_path):
    same = build(tmp_path / "s", "ratio", (1.0, 5.0, 10.0))
    trend = build(tmp_path / "t", "ratio", (1.0, 5.0, 10.0), run=lambda x, s: {"v_low": 0.99 - 0.004 * x})
    assert statuses(results(same, "ratio"), "steady_volume_flat") == ["passed"]
    assert_against(by_tier(trend, "ratio"), "steady_volume_flat")


def test_a_steady_density_scattered_by_a_fifth_of_the_compaction_is_not_resolved(tmp_path):
    # No trend; the runs scatter by 0.02 in V/V0: small beside V/V0 (0.9), a fifth of the
    # compaction 1 - V/V0 (0.1). The data allow a change of 0.037 across the range, more
    # than the margin 0.25 x 0.1; against a margin of V/V0 itself it would have passed.
    values = (0.88, 0.90, 0.92)
    folder = build(tmp_path / "n", "ratio", (1.0, 5.0, 10.0),
                   run=lambda x, s: {"v_low": values[(s + int(x)) % 3]})
    found = results(folder, "ratio")["steady_volume_flat"][0]
    assert found.status == "unresolved", found.reason
    assert "of the compaction 1 - V/V0 = 0.1" in found.reason or "of the compaction 1 - V/V0 = 0.0999" in found.reason
    assert 0.025 < found.detail["allowed_change"] < 0.9 * 0.25


def test_cooling_dilation_weaker_at_small_ratio_passes_and_the_reverse_is_against(tmp_path):
    rising = build(tmp_path / "r", "ratio", (1.0, 5.0, 10.0), run=lambda x, s: {"dilation": 0.001 * x})
    falling = build(tmp_path / "f", "ratio", (1.0, 5.0, 10.0), run=lambda x, s: {"dilation": 0.012 - 0.001 * x})
    flat = build(tmp_path / "n", "ratio", (1.0, 5.0, 10.0),
                 run=lambda x, s: {"dilation": (0.004, 0.008, 0.006)[s]})
    found = results(rising, "ratio")
    assert statuses(found, "cooling_dilation_ratio") == ["passed"]
    assert "steady_time_theta" not in found  # an angle statement
    assert_against(by_tier(falling, "ratio"), "cooling_dilation_ratio")
    assert statuses(results(flat, "ratio"), "cooling_dilation_ratio") == ["unresolved"]


def test_dilation_during_cooling_at_every_angle_passes_and_none_is_against(tmp_path):
    # Fig. 4a: "dilatation is present for all angles theta_c".
    present = results(build(tmp_path / "p", "angle", (0.0, 6.0), run=lambda x, s: {"dilation": 0.005}), "angle")
    assert statuses(present, "cooling_dilation_present") == ["passed", "passed"]
    assert present["cooling_dilation_present"][0].measured == pytest.approx(0.005, rel=0.2)
    none = build(tmp_path / "n", "angle", (0.0,), run=lambda x, s: {"dilation": 0.0})
    assert_against(by_tier(none, "angle"), "cooling_dilation_present")
    assert "no visible dilation" in results(none, "angle")["cooling_dilation_present"][0].reason
    assert "cooling_dilation_present" not in results(build(tmp_path / "r", "ratio", (1.0, 10.0)), "ratio")


def test_dilation_near_the_visible_floor_or_without_a_series_is_not_resolved(tmp_path):
    near = build(tmp_path / "m", "angle", (0.0,), run=lambda x, s: {"dilation": (0.0005, 0.0015, 0.001)[s]})
    found = results(near, "angle")["cooling_dilation_present"][0]
    assert found.status == "unresolved" and "holds 0.001" in found.reason, found.reason
    none = build(tmp_path / "n", "angle", (0.0,), run=lambda x, s: {"series": None})
    assert statuses(results(none, "angle"), "cooling_dilation_present") == ["skipped"]
    short = build(tmp_path / "s", "angle", (0.0,), cycles=4)
    assert statuses(results(short, "angle"), "cooling_dilation_present") == ["skipped"]


def test_a_swing_growing_with_the_ratio_is_not_a_dilation(tmp_path):
    # The container's contraction grows with alpha_c: under the measure of 2026-11-27 (the
    # ends of heating and cooling) this sweep passed; the grains dilate alike at every ratio.
    folder = build(tmp_path / "k", "ratio", (1.0, 5.0, 10.0),
                   run=lambda x, s: {"swing": 0.008 * x, "dilation": (0.004, 0.008, 0.006)[s]})
    assert statuses(results(folder, "ratio"), "cooling_dilation_ratio") == ["unresolved"]


def test_runs_without_a_volume_series_are_left_out_and_said(tmp_path):
    def series(x, s):
        return {"series": None if s == 0 else "volume.csv"}
    some = build(tmp_path / "s", "ratio", (1.0, 5.0, 10.0), run=series)
    found = results(some, "ratio")["steady_volume_flat"][0]
    assert found.status == "passed" and found.detail["without_series"] == 3
    none = build(tmp_path / "n", "ratio", (1.0, 10.0), realizations=2, run=series)  # 2 runs with one
    found = results(none, "ratio")["cooling_dilation_ratio"][0]
    assert found.status == "skipped" and "without a V/V0 series (no volume.csv" in found.reason


def test_without_stage_fields_or_enough_cycles_the_checks_skip(tmp_path):
    folder = build(tmp_path / "a", "angle", (0.0, 4.0), cycles=3, stage=lambda x, s: None)
    found = results(folder, "angle", "quick")
    for check_id in ("stage_heating_direction", "still_zone", "toroidal_cell", "steady_time_theta",
                     "steady_volume_flat"):
        assert set(statuses(found, check_id)) == {"skipped"}, check_id
    assert "outputs.displacement.stages" in found["still_zone"][0].reason
    assert "3 cycle(s)" in found["steady_time_theta"][0].reason


def test_a_bed_too_shallow_for_a_core_skips_the_cell_check(tmp_path):
    folder = build(tmp_path / "a", "angle", (0.0,), realizations=1)
    frame = pd.read_csv(folder / "runs" / "0" / fields.STAGE_FILE)
    frame[frame["iz"] < 3].to_csv(folder / "runs" / "0" / fields.STAGE_FILE, index=False)
    found = results(folder, "angle")  # 3 rows: one row of interior cells, 6 cells
    assert statuses(found, "toroidal_cell") == ["passed"]
    frame[(frame["iz"] < 3) & (frame["ir"] < 3)].to_csv(folder / "runs" / "0" / fields.STAGE_FILE, index=False)
    found = results(folder, "angle")  # 3 x 3 cells: one interior cell
    assert statuses(found, "toroidal_cell") == ["skipped"]
    assert "interior cells per run [1]" in found["toroidal_cell"][0].reason


def test_a_damaged_stage_file_skips_naming_it(tmp_path):
    folder = build(tmp_path / "a", "angle", (0.0,), realizations=1)
    (folder / "runs" / "0" / fields.STAGE_FILE).write_text("cycle,ir\n0,1\n")
    found = results(folder, "angle")
    assert found["still_zone"][0].status == "skipped"
    assert "stage_fields.csv: missing column(s)" in found["still_zone"][0].reason


def test_the_stage_field_figure_is_drawn(tmp_path):
    folder = build(tmp_path / "a", "angle", (0.0, 4.0), realizations=1)
    a = trends.analyse(inputs.load_sweep(folder), "angle", "paper")
    paths, notes = plots.stage_fields_figure(a, tmp_path / "out")
    assert len(paths) == 1 and paths[0].is_file() and not notes
    assert "Fig. 5 and Fig. 6" in paths[0].with_suffix(".txt").read_text()
