"""Tests of scripts/analysis/wall_depth.py and scripts/wall-stress-depth on synthetic
profiles: the growth rate of a profile made from Janssen's form is recovered with its
sign (growth, saturation, hydrostatic), a R pools runs of one width, the width relation
of the peaks gives back its c, and bad inputs are refused before anything is written.

Run with Debian's interpreter: /usr/bin/python3 -m pytest -q scripts/tests/test_wall_depth.py
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy.integrate import quad

SCRIPTS = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(SCRIPTS))

from analysis import wall_depth  # noqa: E402
from analysis.wall_depth_cli import by_radius, main  # noqa: E402

TOOL = SCRIPTS / "wall-stress-depth"
H, BANDS = 15.0, 10


def write(folder: Path, amplitude: float, rate: float, radius: float = 8.5, noise: float = 0.0, seed: int = 0,
          cycles=(0,), peak: float = 100.0, profile: bool = True, angle: float = 0.0,
          wall_friction: float | None = None, realization: int | None = None) -> Path:
    """A run folder whose wall_profile.csv holds Janssen's form averaged over each band
    (by quadrature, not by the module's closed form), plus normal noise of `noise` times
    the hydrostatic mean A H / 2 in every band (the fit's error bars assume one scatter)."""
    rng = np.random.default_rng(seed)
    folder.mkdir(parents=True, exist_ok=True)
    rows = []
    for cycle in cycles:
        for b in range(BANDS):
            z_lo, z_hi = b * H / BANDS, (b + 1) * H / BANDS
            d1, d2 = H - z_hi, H - z_lo
            mean = quad(lambda d: amplitude * (d if rate == 0 else np.expm1(rate * d) / rate), d1, d2)[0] / (d2 - d1)
            rows.append({"cycle": cycle, "t": 30.0 * (cycle + 1), "bin": b, "z_lo": z_lo, "z_hi": z_hi,
                         "wall_stress": mean + noise * amplitude * H / 2 * rng.normal()})
    if profile:
        pd.DataFrame(rows).to_csv(folder / "wall_profile.csv", index=False)
    pd.DataFrame({"cycle": list(cycles), "peak_pressure": peak, "t_peak": 1.0}).to_csv(folder / "cycles.csv",
                                                                                      index=False)
    scene = {"container": {"bottom_radius": radius, "opening_angle_deg": angle}}
    if wall_friction is not None:
        scene["materials"] = {"friction": 0.5, "wall_friction": wall_friction}
    if realization is not None:
        scene["seed"] = realization
    (folder / "run.json").write_text(json.dumps({"status": "completed", "effective_scene": scene}))
    return folder


@pytest.mark.parametrize("rate", [0.25, 0.05, 0.0, -0.15])
def test_the_rate_of_an_exact_profile_is_recovered(tmp_path, rate):
    fit = wall_depth.fit_profile(wall_depth.read_profile(write(tmp_path, 1.7, rate)), 0)
    # Exact data: only the quadrature's and the optimiser's round-off remain.
    assert fit.rate == pytest.approx(rate, abs=1e-6)
    assert fit.amplitude == pytest.approx(1.7, rel=1e-6)
    assert fit.height == pytest.approx(H) and fit.rms_residual < 1e-6


def test_a_noisy_profile_gives_the_rate_within_its_error_and_the_right_sign(tmp_path):
    hits = 0
    for seed in range(20):
        fit = wall_depth.fit_profile(wall_depth.read_profile(write(tmp_path / str(seed), 2.0, 0.2, noise=0.05,
                                                                   seed=seed)), 0)
        assert fit.rate > 0 and fit.rate_se > 0
        hits += abs(fit.rate - 0.2) < 2 * fit.rate_se
    # Two standard errors hold about 92 % of the fits (Student's t with 8 degrees of
    # freedom); fewer than 15 of 20 has a probability of 0.004 when the error bar is right.
    assert hits >= 15


def test_a_rate_times_radius_pools_runs_of_one_width(tmp_path):
    # Exact profiles (abs 1e-5 below): the quadrature's and the optimiser's round-off only.
    fits = [wall_depth.fit_profile(wall_depth.read_profile(write(tmp_path / name, 1.0, 2.0 / radius,
                                                                 radius=radius)), 0)
            for name, radius in (("a", 4.0), ("b", 4.0), ("c", 8.0))]
    groups = by_radius(fits)
    assert list(groups) == [4.0, 8.0]
    assert groups[4.0]["runs"] == 2 and groups[4.0]["rate_times_radius"] == pytest.approx(2.0, abs=1e-5)
    assert groups[8.0]["se"] is None and groups[8.0]["rate_times_radius"] == pytest.approx(2.0, abs=1e-5)


def test_the_width_relation_of_the_peaks_gives_back_its_c(tmp_path):
    radii = [4.25, 6.0, 8.5, 17.0]
    peaks = wall_depth.mean_pressure(radii, 15.0, 1.7, 2.2)
    fit = wall_depth.fit_widths(radii, peaks, 15.0)
    # Exact peaks: the optimiser's round-off only.
    assert fit.c == pytest.approx(2.2, rel=1e-6) and fit.amplitude == pytest.approx(1.7, rel=1e-6)
    assert fit.predicted == pytest.approx(list(peaks), rel=1e-6)
    # The mean of the depth form over [0, H] is the band mean of one band as deep as the bed.
    assert wall_depth.mean_pressure([5.0], 15.0, 1.7, 2.2)[0] == pytest.approx(
        wall_depth.band_mean(np.array([0.0]), np.array([15.0]), 1.7, 2.2 / 5.0)[0], rel=1e-12)
    with pytest.raises(wall_depth.ProfileError, match="at least 3 widths"):
        wall_depth.fit_widths([4.0, 4.0, 8.0], [10.0, 11.0, 3.0], 15.0)


def test_the_angle_relation_of_the_peaks_gives_back_its_friction(tmp_path):
    angles = [0.0, 2.0, 4.0, 6.0, 8.0]
    peaks = wall_depth.angle_pressure(angles, 8.5, 15.0, 1.9, 2.1, 0.25)
    fit = wall_depth.fit_angles(angles, peaks, 8.5, 15.0, 2.1)
    # Exact peaks: rel 1e-5 is the optimiser's stopping tolerance, not a physical one.
    assert fit.mu == pytest.approx(0.25, rel=1e-5) and fit.amplitude == pytest.approx(1.9, rel=1e-5)
    # At 0 deg the angle relation is the width relation.
    assert wall_depth.angle_pressure([0.0], 8.5, 15.0, 1.9, 2.1, 0.25)[0] == pytest.approx(
        wall_depth.mean_pressure([8.5], 15.0, 1.9, 2.1)[0], rel=1e-12)
    # A leaning wall lowers the peak the more, the smaller the friction it has to beat.
    assert wall_depth.angle_pressure([6.0], 8.5, 15.0, 1.9, 2.1, 0.2)[0] < wall_depth.angle_pressure(
        [6.0], 8.5, 15.0, 1.9, 2.1, 0.5)[0] < peaks[0]
    with pytest.raises(wall_depth.ProfileError, match="at least 3 angles"):
        wall_depth.fit_angles([0.0, 6.0, 6.0], [80.0, 27.0, 28.0], 8.5, 15.0, 2.1)


def test_the_tool_fits_the_angles_at_the_width_fits_c(tmp_path, capsys):
    radii, height, c, mu = [4.25, 8.5, 17.0], H, 2.0, 0.3
    folders = [f"w{r:g}={write(tmp_path / f'w{r:g}', 1.0, 0.1, radius=r, peak=wall_depth.mean_pressure([r], height, 1.0, c)[0])}"
               for r in radii]
    leaning = [f"t{t:g}={write(tmp_path / f't{t:g}', 1.0, 0.1, radius=8.5, angle=t, profile=False, peak=wall_depth.angle_pressure([t], 8.5, height, 1.0, c, mu)[0])}"
               for t in (3.0, 6.0)]
    out = tmp_path / "out"
    # Exact synthetic peaks: rel 1e-4 to 1e-5 is the two chained fits' round-off.
    assert main([*folders, *leaning, "--out", str(out)]) == 0
    result = json.loads((out / "wall_depth.json").read_text())
    assert result["widths"]["c"] == pytest.approx(c, rel=1e-5)  # the leaning runs are not in the width fit
    assert result["angles"]["mu"] == pytest.approx(mu, rel=1e-4)
    assert sorted(result["angles"]["angles"]) == [0.0, 3.0, 6.0]
    assert "against the opening angle" in (out / "wall_depth.md").read_text()
    # Leaning runs at two radii, or without the widths' c, are refused.
    other = write(tmp_path / "other", 1.0, 0.1, radius=6.0, angle=6.0, profile=False)
    assert main([*folders, *leaning, f"o={other}", "--out", str(tmp_path / "o1")]) == 2
    assert "the angle fit needs them at one radius" in capsys.readouterr().err
    assert main([folders[1], *leaning, "--out", str(tmp_path / "o2")]) == 2
    assert "the angle fit takes c from the width fit" in capsys.readouterr().err
    assert not (tmp_path / "o1").exists() and not (tmp_path / "o2").exists()


def test_two_peaks_give_back_the_friction_and_k_and_predict_another_wall(tmp_path):
    radius, height, amplitude, k, mu, theta = 8.5, 15.0, 1.8, 5.0, 0.2, 6.0
    p0 = wall_depth.mean_pressure([radius], height, amplitude, 2 * mu * k)[0]
    p6 = wall_depth.angle_pressure([theta], radius, height, amplitude, 2 * mu * k, mu)[0]
    c0 = wall_depth.invert_c(p0, radius, height, amplitude)
    # Exact peaks: brentq's tolerance (1e-14) and the closed forms' round-off only.
    assert c0 == pytest.approx(2 * mu * k, rel=1e-10)
    found_mu, found_k = wall_depth.friction_pair(c0, wall_depth.invert_c(p6, radius, height, amplitude), theta)
    assert found_mu == pytest.approx(mu, rel=1e-9) and found_k == pytest.approx(k, rel=1e-9)
    # At the same K a rougher wall (μ 0.3) raises the 0 deg peak, and its ratio follows from it.
    q0 = wall_depth.mean_pressure([radius], height, amplitude, 2 * 0.3 * k)[0]
    q6 = wall_depth.angle_pressure([theta], radius, height, amplitude, 2 * 0.3 * k, 0.3)[0]
    assert q0 > p0
    assert wall_depth.predicted_ratio(q0, theta, k, radius, height, amplitude) == pytest.approx(q6 / q0, rel=1e-9)
    # Peaks below and above the hydrostatic half are both inverted (g spans (0, inf)).
    for c in (-3.0, 0.0, 7.0):
        p = wall_depth.mean_pressure([radius], height, amplitude, c)[0]
        assert wall_depth.invert_c(p, radius, height, amplitude) == pytest.approx(c, abs=1e-9)
    with pytest.raises(wall_depth.ProfileError, match="expected both positive"):
        wall_depth.invert_c(-1.0, radius, height, amplitude)


def friction_runs(tmp_path, wall: float, k_of_seed, mu_of_seed, radius=8.5, height=H, amplitude=1.0,
                  seeds=(1, 2, 3)) -> list[str]:
    """Runs at 0 and 6 deg of each seed at one wall friction, their peaks made from the form."""
    specs = []
    for s in seeds:
        c = 2 * mu_of_seed(s) * k_of_seed(s)
        for theta in (0.0, 6.0):
            peak = wall_depth.angle_pressure([theta], radius, height, amplitude, c, mu_of_seed(s))[0]
            folder = write(tmp_path / f"f{wall:g}_t{theta:g}_s{s}", 1.0, 0.1, radius=radius, angle=theta,
                           profile=False, peak=peak, wall_friction=wall, realization=s)
            specs.append(f"f{wall:g}_t{theta:g}_s{s}={folder}")
    return specs


def test_the_tool_tests_one_k_across_wall_frictions(tmp_path, capsys):
    c = 2.0
    widths = [f"w{r:g}={write(tmp_path / f'w{r:g}', 1.0, 0.1, radius=r, wall_friction=0.5, realization=1, peak=wall_depth.mean_pressure([r], H, 1.0, c)[0])}"
              for r in (4.25, 6.0, 17.0)]
    k_ref = {1: 5.0, 2: 5.2, 3: 4.9}
    # μ K = c / 2 at every seed of the reference, so its 0 deg peaks lie on the width curve.
    reference = friction_runs(tmp_path, 0.5, k_ref.get, lambda s: c / 2 / k_ref[s])
    same_k = friction_runs(tmp_path, 1.0, k_ref.get, {1: 0.3, 2: 0.28, 3: 0.33}.get)
    out = tmp_path / "out"
    assert main([*widths, *reference, *same_k, "--out", str(out)]) == 0
    result = json.loads((out / "wall_depth.json").read_text())["wall_friction"]
    groups = {g["wall_friction"]: g for g in result["groups"]}
    assert result["reference"] == 0.5 and sorted(groups) == [0.5, 1.0]
    # Each realization's K and μ come back from its two exact peaks (A held at the width
    # fit's, itself exact to its optimiser's 1e-5).
    assert groups[0.5]["k_each"] == pytest.approx([5.0, 5.2, 4.9], rel=1e-4)
    assert groups[1.0]["mu_each"] == pytest.approx([0.3, 0.28, 0.33], rel=1e-4)
    # One K at both frictions: the prediction holds well within its error.
    assert abs(groups[1.0]["z"]) < 1 and groups[1.0]["k_p"] > 0.9
    assert "within two standard errors" in (out / "wall_depth.md").read_text()
    # A wall that changes K is seen: the ratio departs from the prediction.
    other = friction_runs(tmp_path / "other", 1.0, {1: 2.5, 2: 2.6, 3: 2.45}.get, {1: 0.6, 2: 0.56, 3: 0.66}.get)
    assert main([*widths, *reference, *other, "--out", str(tmp_path / "out2")]) == 0
    group = json.loads((tmp_path / "out2" / "wall_depth.json").read_text())["wall_friction"]["groups"][1]
    assert group["z"] > 2 and group["k_p"] < 0.01
    assert "does not hold at this friction" in (tmp_path / "out2" / "wall_depth.md").read_text()
    capsys.readouterr()
    # Refused: the same seed twice at one point, runs at other frictions at two radii.
    again = write(tmp_path / "again", 1.0, 0.1, angle=6.0, profile=False, wall_friction=1.0, realization=1)
    assert main([*widths, *reference, *same_k, f"again={again}", "--out", str(tmp_path / "o3")]) == 2
    assert "are both seed 1 at the wall friction 1.0 and 6 deg" in capsys.readouterr().err
    wide = write(tmp_path / "wide", 1.0, 0.1, radius=17.0, profile=False, wall_friction=1.0, realization=4)
    assert main([*widths, *reference, *same_k, f"wide={wide}", "--out", str(tmp_path / "o4")]) == 2
    assert "the test needs them at one radius" in capsys.readouterr().err
    assert not (tmp_path / "o3").exists() and not (tmp_path / "o4").exists()


def run_tool(*args):
    return subprocess.run(["/usr/bin/python3", str(TOOL), *map(str, args)], capture_output=True, text=True)


def test_the_tool_writes_its_table_figure_and_json(tmp_path):
    peak = dict(zip((4.25, 8.5, 17.0), wall_depth.mean_pressure([4.25, 8.5, 17.0], H, 1.0, 2.0)))
    narrow = write(tmp_path / "narrow", 1.0, 0.3, radius=4.25, peak=peak[4.25])
    wide = write(tmp_path / "wide", 1.0, 0.15, radius=8.5, peak=peak[8.5])
    out = tmp_path / "out"
    # Exact synthetic data throughout: the tolerances below (1e-4 to 1e-5) are the fits' round-off.
    r = run_tool(f"n={narrow}", f"w={wide}", "--out", out)
    assert r.returncode == 0, r.stderr
    result = json.loads((out / "wall_depth.json").read_text())
    assert result["runs"]["n"]["profile"]["rate"] == pytest.approx(0.3, abs=1e-5)
    assert result["runs"]["w"]["profile"]["rate_times_radius"] == pytest.approx(0.15 * 8.5, abs=1e-4)
    assert set(result["by_radius"]) == {"4.25", "8.5"}
    assert result["widths"] is None  # two widths fix no curve of two parameters
    table = (out / "wall_depth.md").read_text()
    assert "| n | 4.25 |" in table and "| w | 8.5 |" in table
    assert (out / "figures" / "wall_depth.png").stat().st_size > 10_000
    assert "n: R 4.25, peak" in r.stdout and "a = +0.3000" in r.stdout
    # A third width, a run without a profile: its peak joins the width fit, which gives
    # back the c the peaks were made with, at the profiles' height.
    widest = write(tmp_path / "widest", 1.0, 0.1, radius=17.0, peak=peak[17.0], profile=False)
    r = run_tool(f"n={narrow}", f"w={wide}", f"x={widest}", "--out", out)
    assert r.returncode == 0, r.stderr
    result = json.loads((out / "wall_depth.json").read_text())
    assert result["runs"]["x"]["profile"] is None and result["runs"]["x"]["peak_pressure"] == peak[17.0]
    assert result["widths"]["height"] == pytest.approx(H)
    assert result["widths"]["c"] == pytest.approx(2.0, rel=1e-5)
    assert "| x | 17 |" in (out / "wall_depth.md").read_text() and "c = 2.000" in r.stdout


@pytest.mark.parametrize("damage, expected", [
    ("no_cycles", "cycles.csv: not a readable CSV"),
    ("bad_profile", "wall_profile.csv: expected the columns"),
    ("height", "--height: expected a positive bed height"),
    ("no_radius", "field 'effective_scene.container.bottom_radius'"),
    ("no_column", "missing wall_stress"),
    ("cycle", "cycles.csv: field 'cycle': no row of cycle 3"),
    ("few_bands", "a fit needs at least 4"),
])
def test_bad_inputs_are_refused_before_anything_is_written(tmp_path, capsys, damage, expected):
    run = write(tmp_path / "run", 1.0, 0.1)
    args = []
    if damage == "no_cycles":
        (run / "cycles.csv").unlink()
    elif damage == "bad_profile":
        (run / "wall_profile.csv").write_text("cycle,bin\n0,0\n")
    elif damage == "height":
        args = ["--height", -1]
    elif damage == "no_radius":
        (run / "run.json").write_text(json.dumps({"effective_scene": {"container": {}}}))
    elif damage == "no_column":
        pd.read_csv(run / "wall_profile.csv").drop(columns="wall_stress").to_csv(run / "wall_profile.csv", index=False)
    elif damage == "cycle":
        args = ["--cycle", 3]
    else:
        table = pd.read_csv(run / "wall_profile.csv")
        table[table["bin"] < 3].to_csv(run / "wall_profile.csv", index=False)
    out = tmp_path / "out"
    assert main([str(run), "--out", str(out), *map(str, args)]) == 2
    err = capsys.readouterr().err
    assert expected in err and (str(run) in err or damage == "height")
    assert not out.exists()
