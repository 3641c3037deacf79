"""The paper's headline trends in a few rows: from a trends.json document, stored as
a dated record (validation/results/*.json), and shown at the top of the validation
report (scripts/report.py). Format: docs/trends.md, "Stored results".

A record holds only what the analysis measured and decided (the checks' statuses come
from scripts/analysis/trends.py); nothing here re-judges a value. This module prepares
the tables as display strings (sections()); the Jinja2 templates
scripts/templates/headline.md.j2 and headline.html.j2, included by the report's
templates, lay them out.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

#: 2: the rules of issue 30 (statuses from resolved intervals, "contradicted").
RECORD_VERSION = 2

#: The headline rows: trend check id, the paper's statement, and the fit of the
#: realization means shown beside it (metric, or None).
ROWS = (
    ("pmax_ratio_6_0", "6 deg opening angle halves the peak wall pressure: P_max(6)/P_max(0) ~ 0.5", None),
    ("pmax_steady", "The peaks P_max averages are in the steady state (Fig. 3a, 3c)", None),
    ("pmax_theta_slope", "P_max falls with the opening angle (Fig. 3b)", "P_max"),
    ("pmax_ratio_slope", "P_max rises with alpha_c/alpha_p (Fig. 3d)", "P_max"),
    ("pmax_ratio_quadratic", "P_max(alpha_c/alpha_p) is fitted well by a quadratic, bending up (Fig. 3d)", "P_max"),
    ("wrms_ratio_slope", "RMS vorticity rises with alpha_c/alpha_p (Fig. 7b)", "W_rms"),
    ("wrms_ratio_quadratic", "RMS vorticity rises roughly quadratically with alpha_c/alpha_p (Fig. 7b)", "W_rms"),
    ("wrms_theta_flat", "RMS vorticity is independent of the opening angle (Fig. 7a)", None),
)
#: Checks of the angle study (the others belong to the ratio study; pmax_steady to both).
ANGLE_IDS = ("pmax_ratio_6_0", "pmax_theta_slope", "wrms_theta_flat")

STATUS_TEXT = {"passed": "PASS", "failed": "FAIL", "unresolved": "NOT RESOLVED",
               "contradicted": "CONTRADICTED", "skipped": "SKIP", "missing": "not measured"}


class RecordError(Exception):
    """A stored record that cannot be read (names the file and the field)."""


def _metric_of(check: str, metric: str) -> str:
    """The summary column a check reads: W_rms[3-6] -> W_rms_3_6."""
    if "[" in check and "]" in check:
        window = check.split("[", 1)[1].split("]", 1)[0]
        return f"{metric}_{window.replace('-', '_')}"
    return metric


def _quadratic(analysis: dict, metric: str) -> dict | None:
    """Coefficients (ascending) and R^2 of the quadratic through the realization means."""
    for name, info in analysis.get("metrics", {}).items():
        if name == metric:
            fit = (info.get("fits_over_means_weighted_by_n") or {}).get("quadratic")
            if fit:
                return {"metric": name, "coefficients": fit["coefficients"], "r2": fit["r2"],
                        "x_range": fit.get("x_range")}
    return None


def from_trends(document: dict, *, engine_commit: str, command: str, scale: str) -> dict:
    """The headline record of one trends.json document."""
    rows = []
    by_kind = {a["kind"]: a for a in document.get("analyses", [])}
    for check_id, statement, metric in ROWS:
        checks = [c for c in document.get("checks", []) if c.get("id") == check_id]
        kind = "angle" if check_id in ANGLE_IDS else "ratio"
        analysis = by_kind.get(kind)
        fit = _quadratic(analysis, metric) if metric and analysis else None
        if not checks:
            rows.append({"id": check_id, "statement": statement, "status": "missing",
                         "measured": None, "check": "", "detail": "", "fit": fit})
            continue
        for c in checks:
            if metric and analysis:
                fit = _quadratic(analysis, _metric_of(c["check"], metric))
            detail = c.get("detail") or {}
            text = c.get("tolerance", "")
            if check_id == "pmax_ratio_6_0" and math.isfinite(detail.get("sigma", math.nan) or math.nan):
                low, high = detail.get("interval") or (math.nan, math.nan)
                text = (f"{detail['ratio']:.3g} +- {detail['sigma']:.2g} (sigma_R), "
                        f"{detail.get('level', 0.95):.0%} interval [{low:.3g}, {high:.3g}], "
                        f"{detail['numerator']['n']} and {detail['denominator']['n']} realizations")
            rows.append({"id": check_id, "statement": statement, "check": c["check"],
                         "status": c["status"], "measured": c.get("measured"), "detail": text,
                         "reason": c.get("reason", ""), "fit": fit})
    return {"version": RECORD_VERSION, "tier": document["tier"], "generated": document["generated"],
            "engine_commit": engine_commit, "command": command, "scale": scale,
            "counts": document.get("counts", {}), "rows": rows}


#: Optional: "reevaluated" (text: how the rows were re-derived under newer rules).
_REQUIRED = {"version": int, "tier": str, "generated": str, "engine_commit": str,
             "command": str, "scale": str, "rows": list}


def load_record(path: Path) -> dict:
    try:
        record = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError) as problem:
        raise RecordError(f"{path}: not a readable JSON record ({problem})") from None
    if not isinstance(record, dict):
        raise RecordError(f"{path}: expected a JSON object")
    for key, kind in _REQUIRED.items():
        if not isinstance(record.get(key), kind):
            raise RecordError(f"{path}: field '{key}' must be a {kind.__name__}")
    if record["version"] != RECORD_VERSION:
        raise RecordError(f"{path}: field 'version' is {record['version']}, expected {RECORD_VERSION}")
    for i, row in enumerate(record["rows"]):
        for key in ("id", "statement", "status"):
            if not isinstance(row.get(key), str):
                raise RecordError(f"{path}: field 'rows[{i}].{key}' must be a string")
        if row["status"] not in STATUS_TEXT:
            raise RecordError(f"{path}: field 'rows[{i}].status' is '{row['status']}', expected one of "
                              f"{', '.join(STATUS_TEXT)}")
    return record


def load_records(folder: Path) -> list[dict]:
    """Every *.json record of the folder, tiers in the order quick, standard, paper."""
    order = {"quick": 0, "standard": 1, "paper": 2}
    records = [load_record(p) for p in sorted(Path(folder).glob("*.json"))] if Path(folder).is_dir() else []
    return sorted(records, key=lambda r: (order.get(r["tier"], 9), r["generated"]))


def _measured(row: dict) -> str:
    if row.get("detail") and row["id"] == "pmax_ratio_6_0":
        return row["detail"]
    value = row.get("measured")
    return "-" if value is None else f"{value:.4g}"


def _fit(row: dict) -> str:
    fit = row.get("fit")
    if not fit:
        return ""
    c0, c1, c2 = fit["coefficients"]
    return f"{fit['metric']} = {c0:.3g} + {c1:.3g} x + {c2:.3g} x^2 (R^2 {fit['r2']:.3f})"


_WHY_PREFIXES = ("not resolved at this scale: ", "contradicted at this scale (reduced): ", "failed: ")


def _why(row: dict) -> str:
    """What the data show, for a row that did not pass: the reason up to the physics."""
    if row["status"] not in ("unresolved", "contradicted", "failed", "missing"):
        return ""
    text = row.get("reason", "").split(". paper:")[0]
    for prefix in _WHY_PREFIXES:
        text = text.removeprefix(prefix)
    return text


def table_rows(record: dict) -> list[dict]:
    return [{"id": r["id"], "statement": r["statement"], "check": r.get("check", ""), "measured": _measured(r),
             "fit": _fit(r), "result": STATUS_TEXT[r["status"]], "why": _why(r)}
            for r in record["rows"]]


def _title(record: dict, source: str) -> str:
    return (f"{source}: {record['tier']} tier, {record['generated']}, engine commit "
            f"{record['engine_commit']}")


def sections(records: list[tuple[str, dict]]) -> list[dict]:
    """One headline table per (source, record), e.g. ("Stored", record): its title,
    scale, command and rows (table_rows), for scripts/templates/headline.*.j2."""
    return [{"title": _title(record, source), "scale": record["scale"], "command": record["command"],
             "reevaluated": record.get("reevaluated", ""), "rows": table_rows(record)}
            for source, record in records]
