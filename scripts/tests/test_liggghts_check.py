"""The verdicts of validation/liggghts/check.py that need no LIGGGHTS run: the cone
ratio's three states and the check line it writes."""

import importlib.util
import json
from pathlib import Path

import pytest

CHECK = Path(__file__).resolve().parents[2] / "validation" / "liggghts" / "check.py"


@pytest.fixture(scope="module")
def check():
    spec = importlib.util.spec_from_file_location("liggghts_check", CHECK)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_a_ratio_above_one_plus_se_fails(check):
    passed, resolved, _ = check.cone_ratio_verdict(1.3, 0.1, 3)
    assert not passed


def test_a_ratio_inside_the_bound_but_not_below_one_is_not_resolved(check):
    # The recorded quick-tier case: NSCD 1.115 with an SE that keeps it under 1 + SE.
    passed, resolved, why = check.cone_ratio_verdict(1.115, 0.153, 3)
    assert passed and not resolved
    assert why.startswith("not resolved: 1.11 +- 0.15 (1 SE)")


def test_one_realization_is_never_resolved(check):
    passed, resolved, why = check.cone_ratio_verdict(0.4, 0.0, 1)
    assert passed and not resolved and "one realization" in why


def test_a_lowering_beyond_one_se_passes(check):
    passed, resolved, why = check.cone_ratio_verdict(0.55, 0.1, 3)
    assert passed and resolved and not why.startswith("not resolved")


def test_the_line_of_a_not_resolved_check(check, tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("RATCHET_CHECKS_DIR", str(tmp_path))
    assert check.record("liggghts_quick_trend", "peak(6 deg) / peak(0 deg), NSCD", 1.115, "< 1.268",
                        "upper bound 1 + 1 SE of the ratio", True, "why", resolved=False)
    assert capsys.readouterr().out.startswith("NOT RESOLVED")
    (path,) = tmp_path.glob("liggghts-*.jsonl")
    line = json.loads(path.read_text())
    assert line["passed"] is True and line["resolved"] is False
    check.record("c", "resolved one", 0.5, "< 1", "t", True, "why")
    second = json.loads(path.read_text().splitlines()[1])
    assert "resolved" not in second
