"""scripts/accuracy-pareto: the relative shifts and their errors it plots must be those of
the comparison it reads (JSON, or the stored markdown table), and a file without the
observable stops it with the file and field named."""

import json
import math
import subprocess
from pathlib import Path

import pytest

TOOL = Path(__file__).resolve().parents[1] / "accuracy-pareto"

COMPARISON = {
    "plan": "validation/accuracy/knob_standard.json", "reference": "fine", "settings": ["fine", "coarse", "mid"],
    "observables": {
        "P_max": {"fine": {"n": 6, "mean": 10.0, "se": 0.5},
                  "coarse": {"n": 6, "mean": 7.0, "se": 0.4, "shift": -3.0, "p": 0.001, "bias": True},
                  "mid": {"n": 6, "mean": 10.5, "se": 1.2, "shift": 0.5, "p": 0.7, "bias": False}},
        "wall_seconds": {"fine": {"n": 6, "mean": 40.0, "se": 1.0}, "coarse": {"n": 6, "mean": 10.0, "se": 0.2},
                         "mid": {"n": 6, "mean": 20.0, "se": 0.5}}}}

MARKDOWN = """# compare-settings: validation/accuracy/knob_standard.json

| observable | `fine` | `coarse` | `mid` |
|---|---|---|---|
| P_max | 10 ± 0.5 | 7 ± 0.4 (p = 0.00, **bias**) | 10.5 ± 1.2 (p = 0.70) |
| wall_seconds | 40 ± 1 | 10 ± 0.2 | 20 ± 0.5 |
"""


def call(*args):
    return subprocess.run(["/usr/bin/python3", str(TOOL), *map(str, args)], capture_output=True, text=True)


def rows_of(md: str) -> dict:
    out = {}
    for line in md.splitlines():
        cells = [c.strip() for c in line.strip("|").split("|")]
        if len(cells) == 6 and cells[1].startswith("`"):
            out[cells[1].strip("`")] = cells
    return out


@pytest.mark.parametrize("name, content", [("knob.json", json.dumps(COMPARISON)), ("knob_standard.md", MARKDOWN)])
def test_shifts_and_errors_are_those_of_the_comparison(tmp_path, name, content):
    src = tmp_path / name
    src.write_text(content)
    r = call(src, "--out", tmp_path / "out")
    assert r.returncode == 0, r.stderr
    rows = rows_of((tmp_path / "out" / "pareto.md").read_text())
    # coarse: (7 - 10) / 10 = -30 %, error hypot(0.4, 0.5) / 10 = 6.4 %; a bias.
    assert rows["coarse"][3] == f"-30.0 ± {100 * math.hypot(0.4, 0.5) / 10:.1f} %"
    assert rows["coarse"][5] == "**bias**"
    assert rows["mid"][3] == f"+5.0 ± {100 * math.hypot(1.2, 0.5) / 10:.1f} %"
    assert rows["mid"][5] == "within the scatter"
    assert rows["fine"][5] == "reference" and rows["fine"][2] == "40"
    assert (tmp_path / "out" / "pareto.png").stat().st_size > 5000
    assert "knob_standard" in (tmp_path / "out" / "pareto.txt").read_text()


def test_a_missing_observable_names_the_file_and_field(tmp_path):
    src = tmp_path / "knob.json"
    src.write_text(json.dumps(COMPARISON))
    r = call(src, "--out", tmp_path / "out", "--observable", "W_rms_0_1")
    assert r.returncode == 2
    assert f"{src}: field 'observables.W_rms_0_1': missing" in r.stderr
    assert not (tmp_path / "out").exists()
