"""Writing the results: check lines (JSONL), trends.json, trends.md, the terminal table.

Every file is written atomically (common.fsutil.write_atomic: a temporary file in the
same folder, then a rename), so a reader never sees a partial file.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
from pathlib import Path
from typing import Iterable

from common.figures import figure_caption
from common.fsutil import write_atomic


def slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "-", text).strip("-").lower() or "sweep"


# --------------------------------------------------------------------------- checks


def checks_file_name(folders: Iterable[Path]) -> str:
    """trends-<names>-<hash>.jsonl: the same sweeps give the same file (a rerun replaces
    it), different sweeps analysed separately into one checks folder do not collide."""
    resolved = [str(Path(f).resolve()) for f in folders]
    digest = hashlib.sha1("\n".join(sorted(resolved)).encode()).hexdigest()[:8]
    names = "+".join(slug(Path(r).name) for r in resolved)[:60]
    return f"trends-{names}-{digest}.jsonl"


def write_checks(folder: Path, name: str, results) -> Path | None:
    """One JSON line per passed, failed, not-resolved or contradicted check (skipped
    ones have no such state).
    With none, an earlier file of the same name is removed (it would not describe
    this run). Returns the path written, or None."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / name
    lines = [json.dumps(r.record(), allow_nan=False) for r in results if r.status != "skipped"]
    if not lines:
        if path.exists():
            path.unlink()
        return None
    write_atomic(path, "\n".join(lines) + "\n")
    return path


# --------------------------------------------------------------------------- tables


def _measured(value) -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    return f"{value:.6g}"


RESULT_TEXT = {"passed": "PASS", "failed": "FAIL", "unresolved": "NOT RESOLVED",
               "contradicted": "CONTRADICTED", "skipped": "SKIP"}


def terminal_table(results) -> str:
    columns = ("case", "check", "measured", "expected", "tolerance", "result")
    rows = [{"case": r.case, "check": r.check, "measured": _measured(r.measured),
             "expected": r.expected, "tolerance": r.tolerance,
             "result": RESULT_TEXT[r.status]} for r in results]
    widths = {c: max([len(c)] + [len(row[c]) for row in rows]) for c in columns}
    widths["tolerance"] = min(widths["tolerance"], 60)
    lines = [" | ".join(c.ljust(widths[c]) for c in columns).rstrip(),
             "-+-".join("-" * widths[c] for c in columns)]
    for row in rows:
        tol = row["tolerance"]
        if len(tol) > 60:
            row = dict(row, tolerance=tol[:57] + "...")
        lines.append(" | ".join(row[c].ljust(widths[c]) for c in columns).rstrip())
    return "\n".join(lines)


def counts(results) -> dict:
    out = {"passed": 0, "failed": 0, "unresolved": 0, "contradicted": 0, "skipped": 0}
    for r in results:
        out[r.status] += 1
    return out


def _md(text) -> str:
    return " ".join(str(text).split()).replace("|", "\\|") or " "


def _num(value, digits: int = 4) -> str:
    if value is None:
        return "-"
    value = float(value)
    return f"{value:.{digits}g}" if math.isfinite(value) else "-"


def render_markdown(meta: dict, analyses, results, figures: list[Path], notes: list[str],
                    out_dir: Path) -> str:
    total = counts(results)
    verdict = ("FAILED" if total["failed"] else
               "NO FAILURE, CONTRADICTED AT REDUCED SCALE" if total["contradicted"] else "PASSED")
    out = ["# Paper trends", ""]
    for key, value in meta.items():
        out.append(f"- {key}: {value}")
    out += [f"- Checks: {total['passed']} passed, {total['failed']} failed, "
            f"{total['unresolved']} not resolved, {total['contradicted']} contradicted at reduced "
            f"scale, {total['skipped']} skipped", "",
            f"**{verdict}**" + (" (skipped checks lacked data; they are not passes)"
                                if total["skipped"] else ""), "",
            "## Checks", "",
            "| case | check | measured | expected | tolerance | result | reason |",
            "|---|---|---|---|---|---|---|"]
    for r in results:
        result = {"passed": "PASS", "failed": "**FAIL**", "unresolved": "*NOT RESOLVED*",
                  "contradicted": "**CONTRADICTED**", "skipped": "SKIP"}[r.status]
        out.append(f"| {_md(r.case)} | {_md(r.check)} | {_measured(r.measured)} | "
                   f"{_md(r.expected)} | {_md(r.tolerance)} | {result} | {_md(r.reason)} |")
    if notes:
        out += ["", "## Notes", ""] + [f"- {_md(n)}" for n in notes]
    for a in analyses:
        out += ["", f"## {a.case}", "",
                f"Sweep folder `{a.sweep.folder}`; parameter {a.x_label} (column `{a.x}`); "
                f"{len(a.data)} completed runs analysed."]
        for note in a.notes:
            out.append(f"\n- {_md(note)}")
        for metric, info in a.metrics.items():
            out += ["", f"### {metric} vs {a.x_label}", "",
                    f"| {a.x_label} | n | mean | std | sem |", "|---|---|---|---|---|"]
            for row in info["groups"].itertuples(index=False):
                out.append(f"| {row.x:g} | {row.n} | {_num(row.mean, 6)} | {_num(row.std)} | "
                           f"{_num(row.sem)} |")
            out += ["", "| fit | data | c0 | c1 | c2 | R^2 | n | dof |",
                    "|---|---|---|---|---|---|---|---|"]
            for source, label in (("realizations", "all realizations, unweighted"),
                                  ("means", "means, weighted by n")):
                for name in ("linear", "quadratic"):
                    fit = info[source][name]
                    if fit is None:
                        why = info["why_not"].get(name, "too few points")
                        out.append(f"| {name} | {label} | {_md(why)} | | | | | |")
                        continue
                    cells = []
                    for i in range(3):
                        if i < len(fit.coef):
                            se = fit.se[i]
                            cells.append(_num(fit.coef[i]) + (f" ± {_num(se, 2)}"
                                                             if math.isfinite(se) else ""))
                        else:
                            cells.append("")
                    out.append(f"| {name} | {label} | {' | '.join(cells)} | {_num(fit.r2)} | "
                               f"{fit.n} | {fit.dof} |")
        if a.halving is not None:
            h = a.halving
            out += ["", f"P_max(6 deg)/P_max(0 deg) = {_num(h['ratio'])} ± {_num(h['sigma'])} "
                        f"({h['propagation']}; n = {h['numerator']['n']} and "
                        f"{h['denominator']['n']} realizations; Welch-Satterthwaite dof "
                        f"{_num(h['dof'], 3)})"]
        if a.steady:
            out += ["", "Steady state of the peaks (check `pmax_steady`): " + "; ".join(
                f"{a.point_label(v)} {s['state']}" for v, s in sorted(a.steady.items()))]
    if figures:
        out += ["", "## Figures"]
        for figure in figures:
            link = os.path.relpath(figure, out_dir).replace(os.sep, "/")
            caption = figure_caption(figure)
            out += ["", f"### {figure.stem}", "", _md(caption), "", f"![{figure.stem}]({link})"]
    return "\n".join(out) + "\n"


def analysis_json(a) -> dict:
    metrics = {}
    for metric, info in a.metrics.items():
        metrics[metric] = {
            "groups": info["groups"],
            "n_runs": info["n_runs"],
            "fits_over_realizations": {k: (v.to_dict() if v is not None else None)
                                       for k, v in info["realizations"].items()},
            "fits_over_means_weighted_by_n": {k: (v.to_dict() if v is not None else None)
                                              for k, v in info["means"].items()},
            "why_no_fit": info["why_not"],
        }
    return {
        "case": a.case, "kind": a.kind, "parameter": a.x, "parameter_label": a.x_label,
        "runs_analysed": [int(r) for r in a.data["run"]],
        "metrics": metrics,
        "ratio_6_over_0": a.halving,
        "volume": {k: v for k, v in a.volume.items()},
        "steady": {f"{v:g}": s for v, s in sorted(a.steady.items())},
        "checks": [r.to_dict() for r in a.results],
        "notes": a.notes,
    }
