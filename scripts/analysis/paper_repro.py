"""The paper, figure by figure: each checkable statement of the paper (Table 1, Figs.
3a-d, 4a-b, 5, 6, 7a-b and the halving of the peak pressure at 6 deg) with the
paper's words, the checks that test it and their verdict at the paper's scale, the
runs behind the verdict, what the campaign has still to run, and the verdicts of
reduced scales beside it, labelled as such (docs/paper-reproduction.md).

The data are the campaign's stored runs (validation/results/<plan>/<point>/seed<s>/,
docs/campaign.md). They are assembled into sweep folders by the campaign's own
assemble() and judged by trends.analyse at the paper tier, so every verdict is the
one scripts/trends gives on the same runs; nothing here re-judges a value. build()
returns plain values (and figure paths) for the templates paper_repro.md.j2 and
paper_repro.html.j2, which scripts/report.py and scripts/paper-repro render.
"""

from __future__ import annotations

import datetime as _dt
import json
import math
import shutil
import statistics
import sys
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace

from campaign_lib import store
from campaign_lib.assemble import assemble, lookup
from campaign_lib.plan import Plan, PlanError, load_plan, same_json
from campaign_lib.state import one_thread_seconds, point_medians
from common.figures import figure_caption
from common.fsutil import write_atomic
from common.paths import REPO_ROOT, shown

from . import fields, headline, paper_figures, plots, trends
from .verdict_text import RESULT_CLASS, result_text
from .inputs import ALPHA_C, ANGLE, InputError, load_sweep

DEFAULT_PLAN = REPO_ROOT / "validation" / "campaigns" / "paper.json"
DEFAULT_RESULTS = REPO_ROOT / "validation" / "results" / "paper"
# The compliance ladders on the paper's bed (scripts/compare-settings comparisons, kept in
# validation/results/accuracy/; docs/accuracy-cost.md, "The compliance at the paper's
# depth", "The spring law at the paper's depth" and "The rigid law at the paper's depth"):
# (cone angle, file). Settings 'e<eps>' are the creep law's, 's<eps>' the spring law's,
# 'rigid' the paper's law (eps = 0). A missing file is left out.
_ACCURACY = REPO_ROOT / "validation" / "results" / "accuracy"
LAW_LADDERS = ((0.0, _ACCURACY / "law_ladder_paper.json"), (6.0, _ACCURACY / "law_ladder_paper6.json"),
               (0.0, _ACCURACY / "spring_ladder_paper.json"), (6.0, _ACCURACY / "spring_ladder_paper6.json"),
               (0.0, _ACCURACY / "law_paper.json"))
_RIGID = "rigid"  # the setting that names the paper's law
_LADDER_LAWS = {"s": "spring", "e": "creep"}  # setting prefix -> law, in the order of the table's rows
_LAW_RANK = {law: i for i, law in enumerate((_RIGID, *_LADDER_LAWS.values()))}
TITLE = "The paper, figure by figure"
#: The kind of study of a plan part, by the scene path it sweeps.
KIND_OF_SWEEP = {ANGLE: "angle", ALPHA_C: "ratio"}


class PaperReproError(Exception):
    """A plan or stored result that cannot be used; the message names the file and field."""


@dataclass(frozen=True)
class Statement:
    id: str            # the anchor of its section
    figure: str        # where the paper says it
    topic: str
    quote: str         # the paper's words
    parts: tuple       # the plan parts whose runs test it
    checks: tuple      # check ids of trends.CHECKS
    figures: tuple     # (part, figure) drawn from that part's runs (FIGURES)
    gap: str = ""      # what of the statement no check tests


#: The paper's checkable statements, in the paper's order. The quotes are the paper's
#: (Iliev et al., "Behavior of confined granular beds under cyclic thermal loading").
STATEMENTS = (
    Statement("table1", "Table 1", "The simulation parameters",
              "Summary of typical values of the dimensionless simulation parameters: "
              "N_p = 2000, r_c = 8.5, r_min = 0.5, r_max = 1.0, T_0 = 0, T_1 = 100, "
              "alpha_p = 1e-4, alpha_c = 1e-3.",
              ("halving", "ratio", "angle"), (), ()),
    Statement("fig3a", "Fig. 3a", "Pressure over the cycles at each opening angle",
              "two regimes appear for all parameters [...] a steady state is reached where the "
              "pressure fluctuates around a relatively constant value [...] The first regime is due "
              "to compaction of the granular material, since pressure increases as the total "
              "packing density increases. [...] the steady state is reached quicker with increasing "
              "theta_c and [...] the pressure peaks at the steady state decrease with increasing "
              "theta_c.",
              ("angle",), ("pmax_steady", "pmax_rise", "pmax_follows_density", "steady_time_theta"),
              (("angle", "peaks"), ("angle", "density"))),
    Statement("fig3b", "Fig. 3b", "Mean peak pressure against the opening angle",
              "The dependence of the mean peak pressure P_max on theta_c [...] appears to be "
              "approximated well by a quadratic function, but does not deviate strongly from a "
              "linear relation either.",
              ("angle",), ("pmax_theta_slope",), (("angle", "P_max"),),
              gap="the shape (quadratic or line) is fitted and drawn, not checked: the paper "
                  "itself calls either fit good; the check is the fall with theta_c"),
    Statement("halving", "Results text", "A 6 deg cone halves the peak pressure",
              "Remarkably, a conical container with an opening angle of only 6 deg halves the "
              "peak pressure compared to a cylindrical container.",
              ("halving",), ("pmax_ratio_6_0",), (("halving", "halving"),)),
    Statement("fig3c", "Fig. 3c", "Pressure over the cycles at each expansion ratio",
              "It is evident that alpha_c/alpha_p introduces a time scale that determines the "
              "rate of peak pressure increase as a function of the number of cycles.",
              ("ratio",), ("pmax_steady", "pmax_rise", "pmax_follows_density", "steady_time_ratio"),
              (("ratio", "peaks"), ("ratio", "density")),
              gap="which way the time scale moves: the paper names none, so steady_time_ratio "
                  "(the cycles to the steady state against the ratio) passes either sign"),
    Statement("fig3d", "Fig. 3d", "Mean peak pressure against the expansion ratio",
              "the peak pressure increases with increasing alpha_c/alpha_p as expected and is "
              "fitted well by a quadratic function.",
              ("ratio",), ("pmax_ratio_slope", "pmax_ratio_quadratic"), (("ratio", "P_max"),)),
    Statement("fig4a", "Fig. 4a", "Bed volume over the cycles at each opening angle",
              "We observe a decrease in the volume [...] for the first few cycles during the "
              "compaction regime, which is followed by a saturation [...] dilatation is present "
              "for all angles theta_c.",
              ("angle",), ("volume_end", "volume_saturation", "steady_volume_flat", "cooling_dilation_present"),
              (("angle", "volume"),)),
    Statement("fig4b", "Fig. 4b", "Bed volume over the cycles at each expansion ratio",
              "we observe that the magnitude of dilatation decreases with decreasing alpha_c.",
              ("ratio",), ("cooling_dilation_ratio", "volume_end", "volume_saturation",
                           "steady_volume_flat"), (("ratio", "volume"),)),
    Statement("fig5", "Fig. 5", "Displacements during a heating and a cooling stage",
              "As the system expands during the temperature increase, particles [...] motion from "
              "the central axis outwards and downwards. A conical zone at the bottom of the system "
              "with almost no displacements can also be seen [...] as the system contracts [...] "
              "the shrinking walls of the container push the particles inwards and upwards.",
              ("angle", "ratio"), ("stage_heating_direction", "stage_cooling_direction",
                                   "still_zone"), (("angle", "stage_fields"),)),
    Statement("fig6", "Fig. 6", "Accumulated displacement and vorticity: convection cells",
              "One immediately notices the formation of convection cells in the bed [...] the "
              "convection cells take the form of a toroidal vortex. The convection cells were "
              "observed for all combinations of system parameters investigated in this study. "
              "[...] The magnitude of the vorticity in the first 10 cycles is higher than in the "
              "second 10 cycles because when the system has lower density, the particles can move "
              "more freely faster.",
              ("angle", "ratio"), ("toroidal_cell", "wrms_early_larger"),
              (("angle", "displacement"), ("angle", "stage_fields"))),
    Statement("fig7a", "Fig. 7a", "RMS vorticity against the opening angle",
              "Within the error bars, W_rms is practically independent of theta_c at any stage of "
              "the thermal cycling.",
              ("angle",), ("wrms_theta_flat",), (("angle", "W_rms"),)),
    Statement("fig7b", "Fig. 7b", "RMS vorticity against the expansion ratio",
              "the dependence of alpha_c/alpha_p on W_rms appears to be well fitted by a quadratic "
              "function [...] the magnitude of the vorticity increases monotonically with alpha_c "
              "and the deviation from the linear approximation is stronger in the steady state, "
              "i.e., after the first 10 cycles.",
              ("ratio",), ("wrms_ratio_slope", "wrms_ratio_monotone", "wrms_ratio_quadratic",
                          "wrms_ratio_bend_later"),
              (("ratio", "W_rms"),)),
)

#: The figures a statement can ask for: scripts/trends' own (plots.py) and the two of
#: paper_figures.py.
FIGURES = {
    "peaks": paper_figures.peaks_per_cycle,
    "density": paper_figures.pressure_density,
    "halving": paper_figures.halving,
    "P_max": plots.metric_vs_parameter,
    "volume": plots.volume_vs_time,
    "W_rms": plots.wrms_vs_parameter,
    "displacement": plots.displacement_fields,
    "stage_fields": plots.stage_fields_figure,
}

#: Table 1 and the text's other set-up numbers: (parameter, symbol, the paper's value,
#: the scene path, where the paper says it). Compared with the scene of every planned run.
TABLE1 = (
    ("Number of particles", "N_p", 2000, "particles.generate.count", "Table 1"),
    ("Container radius", "r_c", 8.5, "container.bottom_radius", "Table 1"),
    ("Minimum particle radius", "r_min", 0.5, "particles.generate.radius_range.0", "Table 1"),
    ("Maximum particle radius", "r_max", 1.0, "particles.generate.radius_range.1", "Table 1"),
    ("Lowest temperature", "T_0", 0, "thermal.T0", "Table 1"),
    ("Highest temperature", "T_1", 100, "thermal.T1", "Table 1"),
    ("Thermal expansion coefficient", "alpha_p", 1e-4, "thermal.alpha_p", "Table 1"),
    ("Thermal expansion coefficient", "alpha_c", 1e-3, "thermal.alpha_c",
     "Table 1 (varied in the ratio study)"),
    ("Container segments", "", 16, "container.segments", "text: 'discretized by 16 planar segments'"),
    ("Thermal cycles", "", 20, "thermal.cycles", "Figs. 2 and 6: 20 cycles"),
)

#: The checks that read a run's stage_fields.csv (analysis/fields.py).
STAGE_CHECKS = ("stage_heating_direction", "stage_cooling_direction", "still_zone", "toroidal_cell")

NOT_RUN = "NOT YET RUN at the paper's scale"


def _hours(seconds: float) -> str:
    return f"{seconds / 3600:.1f} CPU h"


def _seeds(seeds) -> str:
    seeds = sorted(seeds)
    if len(seeds) > 2 and seeds == list(range(seeds[0], seeds[-1] + 1)):
        return f"seeds {seeds[0]}-{seeds[-1]}"
    return ("seed " if len(seeds) == 1 else "seeds ") + ", ".join(str(s) for s in seeds)


def _value(scene: dict, path: str):
    """A scene value by dotted path; a number in the path indexes a list."""
    node = scene
    for key in path.split("."):
        if isinstance(node, list) and key.isdigit() and int(key) < len(node):
            node = node[int(key)]
        elif isinstance(node, dict) and key in node:
            node = node[key]
        else:
            return None
    return node


# --------------------------------------------------------------------------- the runs


@dataclass
class Runs:
    """What the stored results hold for the plan."""

    plan: Plan
    results: Path
    used: dict          # run label -> store.Stored: current for the plan's scene
    refused: list       # "label: why" of stored folders not used
    run_seconds: float  # one run's cost for "still to run", at a point with no stored run
    cost_source: str
    point_seconds: dict = field(default_factory=dict)  # point -> its stored runs' median cost

    def cost(self, points: list) -> tuple[float, str]:
        """The one-thread seconds of the runs missing at these points and how they were
        estimated: a point's own stored runs where it has some (the cost depends on the
        point: the ratio-1 runs are several times cheaper than the ratio-10 ones)."""
        seconds = sum(len(self.missing(p)) * self.point_seconds.get(p, self.run_seconds) for p in points)
        own = [p for p in points if self.missing(p) and p in self.point_seconds]
        source = self.cost_source + (f"; {', '.join(own)} at the median of their own" if own else "")
        return seconds, source

    def stored(self, point: str) -> list:
        return [r.seed for r in self.plan.runs if r.point.name == point and r.label in self.used]

    def missing(self, point: str) -> list:
        return [r.seed for r in self.plan.runs if r.point.name == point and r.label not in self.used]


def survey(plan: Plan, results: Path) -> Runs:
    """The stored runs whose scene is the plan's (reuse rule 1 of docs/campaign.md, the
    part that needs no engine; which engine made each is shown). A folder without
    provenance.json or a completed run.json is not a stored run."""
    used, refused = {}, []
    for run in plan.runs:
        stored = store.read(results, run)
        if stored is None:
            folder = store.folder_of(results, run)
            if folder.is_dir() and any(folder.iterdir()):
                refused.append(f"{run.label}: no {store.PROVENANCE} or no completed run.json in "
                               f"{shown(folder)} (not a stored run)")
            continue
        if not same_json(stored.run_json.get("scene"), plan.scene_for(run)):
            refused.append(f"{run.label}: field 'scene' of {shown(stored.folder / 'run.json')} "
                           "differs from the plan's scene (plan or base scene changed since): not "
                           "used; the campaign reruns it")
            continue
        used[run.label] = stored
    # A run's one-thread CPU time, as the campaign estimates it (a run resumed on two
    # threads spent twice its wall in CPU).
    cost = {label: one_thread_seconds(s.provenance) for label, s in used.items()}
    cpu = [c for c in cost.values() if c is not None]
    point_seconds = {point: median for point, (median, _) in point_medians(
        (r.point.name, cost[r.label]) for r in plan.runs if cost.get(r.label) is not None).items()}
    if cpu:
        seconds, source = statistics.median(cpu), f"the median of {len(cpu)} stored run(s)"
    else:
        seconds = plan.run_cost_hours * 3600.0
        source = f"the plan's run_cost_hours, {plan.run_cost_hours:g} h a run"
    return Runs(plan=plan, results=results, used=used, refused=refused, run_seconds=seconds,
                cost_source=source, point_seconds=point_seconds)


def analyse(runs: Runs, work: Path) -> dict:
    """Every plan part with a stored run, assembled as a sweep folder (the campaign's
    assemble(), as `scripts/campaign PLAN --assemble`) and analysed at the paper tier:
    part name -> trends.Analysis."""
    states = [SimpleNamespace(run=r, done=r.label in runs.used, stored=runs.used.get(r.label))
              for r in runs.plan.runs]
    sweeps = work / "sweeps"
    shutil.rmtree(sweeps, ignore_errors=True)
    if not runs.used:
        return {}
    sweeps.mkdir(parents=True, exist_ok=True)
    folders = assemble(runs.plan, states, sweeps, lambda message: None)
    analyses = {}
    for part, folder in zip(runs.plan.parts, folders):
        kind = KIND_OF_SWEEP.get(part.sweep)
        if kind is None or not any(r.label in runs.used for r in runs.plan.part_runs(part)):
            continue
        try:
            sweep = load_sweep(folder)
        except InputError as problem:
            raise PaperReproError(str(problem)) from None
        analyses[part.name] = trends.analyse(sweep, kind, trends.PAPER_TIER)
    return analyses


# --------------------------------------------------------------------------- statements


def _part(plan: Plan, name: str):
    for part in plan.parts:
        if part.name == name:
            return part
    raise PaperReproError(f"{plan.path}: field 'parts': no part named '{name}' (the paper's "
                          f"statements read the parts {', '.join(_needed_parts())})")


def _needed_parts() -> list:
    return sorted({p for s in STATEMENTS for p in s.parts})


def _points(plan: Plan, statement: Statement) -> list:
    names = []
    for part in statement.parts:
        names += [p for p in _part(plan, part).points if p not in names]
    return names


def _scale(runs: Runs, points: list) -> dict:
    """The bed behind a verdict and the realizations stored per point."""
    scene = runs.plan.scene_for(runs.plan.runs[0])
    bed = (f"the plan's bed, {lookup(scene, 'particles.generate.count')} polyhedra, "
           f"{lookup(scene, 'thermal.cycles')} cycles")
    per_point = [f"{p} {len(runs.stored(p))} of {len(runs.plan.points[p].seeds)}" for p in points]
    stored = sum(len(runs.stored(p)) for p in points)
    planned = sum(len(runs.plan.points[p].seeds) for p in points)
    return {"stored": stored, "planned": planned,
            "text": f"{bed}; {stored} of {planned} planned runs stored (realizations per point: "
                    f"{', '.join(per_point)})"}


def _missing(runs: Runs, points: list) -> str:
    parts = [f"{p} {_seeds(runs.missing(p))}" for p in points if runs.missing(p)]
    count = sum(len(runs.missing(p)) for p in points)
    if not count:
        return "nothing: every planned run is stored"
    seconds, source = runs.cost(points)
    return f"{count} run(s): {'; '.join(parts)} (about {_hours(seconds)} at {source})"


def _why(reason: str) -> str:
    """What the data show, without the physics and the tier's reason that follow."""
    text = reason.split(". paper:")[0]
    for prefix in ("not resolved at this scale: ", "contradicted at this scale (reduced): ",
                   "failed: ", "skipped: "):
        text = text.removeprefix(prefix)
    return text


def _papers_point_label(a) -> str:
    """How a's per-point checks name the paper's own point (theta_c = 0, alpha_c/alpha_p =
    10), which both studies hold: the same stored runs."""
    return f"({a.point_label(trends.PAPER_VALUE[a.kind])})"


def _check_rows(analyses: dict, statement: Statement) -> list:
    rows = []
    shared_shown = False
    for part in statement.parts:
        a = analyses.get(part)
        shared = _papers_point_label(a) if a else ""
        shown_here = False
        for r in (a.results if a else []):
            if r.check_id not in statement.checks:
                continue
            if shared in r.check:
                if shared_shown:
                    continue  # the paper's point judged once: its runs are those of the part before
                shown_here = True
            verdict = result_text(r.status, r.measured)
            measured = r.measured
            rows.append({"id": r.check_id, "case": r.case, "check": r.check,
                         "measured": "-" if measured is None or not math.isfinite(measured)
                         else f"{measured:.4g}",
                         "tolerance": r.tolerance, "result": verdict,
                         "result_class": RESULT_CLASS[verdict],
                         "why": "" if verdict == "PASS" else _why(r.reason)})
        shared_shown = shared_shown or shown_here
    order = {c: i for i, c in enumerate(statement.checks)}
    return sorted(rows, key=lambda row: order[row["id"]])


_COUNT_WORDS = (("PASS", "passed"), ("NOT RESOLVED", "not resolved"),
                ("CONTRADICTED", "contradicted"), ("FAIL", "failed"), ("SKIP", "skipped"))
#: The verdict of a statement from its checks' results: the first of these present.
_VERDICT_ORDER = (("FAIL", "FAILED", "fail"), ("CONTRADICTED", "CONTRADICTED", "contradicted"),
                  ("NOT RESOLVED", "NOT RESOLVED", "unresolved"), ("PASS", "PASSED", "pass"))


def _verdict(rows: list, scale: dict) -> tuple[str, str]:
    if not scale["stored"]:
        return NOT_RUN, "notrun"
    shown = [r["result"] for r in rows]
    counts = ", ".join(f"{shown.count(t)} {word}" for t, word in _COUNT_WORDS if shown.count(t))
    provisional = ("" if scale["stored"] == scale["planned"] else
                   f"; provisional: {scale['stored']} of {scale['planned']} runs")
    for key, text, css in _VERDICT_ORDER:
        if key in shown:
            return f"{text} ({counts}{provisional})", css
    return f"NOT CHECKED: every check skipped ({counts}{provisional})", "skip"


def _other_studys_point(statement: Statement, check: str) -> bool:
    """A per-point check of a study the statement does not read (pmax_steady at an
    alpha_c/alpha_p under Fig. 3a, which is about theta_c)."""
    studies = [p for p in statement.parts if p in trends.X_LABELS]
    return bool(studies) and any(f"({label}=" in check for kind, label in trends.X_LABELS.items()
                                 if kind not in studies)


def _reduced(statement: Statement, reduced) -> list:
    """The stored and this run's headline records (analysis/headline.py) for the
    statement's checks: reduced scales, never the paper-scale verdict."""
    out = []
    for source, record in reduced:
        scale = ("paper tier (a stored trends record)" if record["tier"] == trends.PAPER_TIER
                 else "REDUCED SCALE, not the paper's verdict")
        label = (f"{source}: {record['tier']} tier, {record['generated']}, engine commit "
                 f"{record['engine_commit']} ({scale})")
        for row in headline.table_rows(record):
            if row["id"] in statement.checks and not _other_studys_point(statement, row["check"] or ""):
                out.append({"label": label, "tier": record["tier"], "source": source,
                            "check": row["check"] or row["statement"],
                            "measured": row["measured"], "result": row["result"],
                            "result_class": RESULT_CLASS.get(row["result"], "skip"),
                            "why": row["why"]})
    return out


def _reduced_summary(rows: list) -> str:
    """One line for the overview: each record's results, e.g. 'stored standard tier:
    PASS, NOT RESOLVED'."""
    seen = {}
    for row in rows:
        seen.setdefault(f"{row['source'].lower()} {row['tier']} tier", []).append(row["result"])
    return "; ".join(f"{k}: {', '.join(dict.fromkeys(v))}" for k, v in seen.items()) or "none"


def _table1(plan: Plan) -> tuple[list, str, str]:
    """Table 1 against the scenes of every planned run."""
    rows, differ = [], []
    scenes = [plan.scene_for(r) for r in plan.runs]
    for name, symbol, paper, path, where in TABLE1:
        values = []
        for scene in scenes:
            value = _value(scene, path)
            if value not in values:
                values.append(value)
        numbers = [v for v in values if isinstance(v, (int, float)) and not isinstance(v, bool)]
        match = any(math.isclose(v, paper, rel_tol=1e-12, abs_tol=0.0) for v in numbers)
        varied = len(values) > 1
        if not match or (varied and "varied" not in where):
            differ.append(symbol or name)
        rows.append({"name": name, "symbol": symbol, "paper": f"{paper:g}", "where": where,
                     "path": path, "ours": ", ".join("not set" if v is None else f"{v:g}"
                                                      if isinstance(v, (int, float)) else str(v)
                                                      for v in values),
                     "result": "PASS" if match and (not varied or "varied" in where) else "FAIL"})
    for row in rows:
        row["result_class"] = RESULT_CLASS[row["result"]]
    if differ:
        return rows, f"DIFFERS: {', '.join(differ)}", "fail"
    return rows, f"MATCHES: every value of the plan's {len(plan.runs)} runs", "pass"


def _law(plan: Plan) -> str:
    """The contact law of the plan's runs (solver.compliance and solver.tangential_law;
    absent: the engine's defaults, rigid and creep, docs/scene-format.md), against the
    paper's rigid law."""
    scenes = [plan.scene_for(r) for r in plan.runs]
    values = sorted({float(_value(scene, "solver.compliance") or 0.0) for scene in scenes})
    if values == [0.0]:
        return "rigid (solver.compliance 0), as the paper's"
    shown = ", ".join(f"{v:g}" for v in values)
    laws = sorted({str(_value(scene, "solver.tangential_law") or "creep") for scene in scenes})
    tangential = ", ".join(laws)
    creep = (" (sticking contacts creep at c λ_t, so the peaks also depend on how long a stage lasts: "
             "docs/accuracy-cost.md, The stage durations at the paper's depth)") if "creep" in laws else ""
    if creep:
        measured = ("On the paper's bed the law moves the peak pressure and the halving ratio (the ladders below "
                    "the table)")
    else:
        measured = ("On the paper's bed the spring law's P_max and vorticity at ε = 0.01 are within the scatter of "
                    "ε = 0.003; with the cycle twice "
                    "as long the first two cycles' peaks stay within 3 % but the pressure held after a cooling "
                    "doubles; against the paper's rigid law on 3 beds no observable's shift is resolved (Welch "
                    "p ≥ 0.08; V/V0 the same bed by bed within 0.0013, while the rigid wall pressure scatters "
                    "six times more between beds) "
                    "(the ladders below the table; docs/accuracy-cost.md, The spring law at the paper's depth, "
                    "The rigid law at the paper's depth)")
    return (f"compliant, ε = {shown} (solver.compliance), tangential law {tangential}{creep}; the paper's law "
            f"is rigid. {measured}: the verdicts are those of this law")


def _ladders(ladders) -> tuple[list, dict]:
    """Per tangential law and compliance of the ladders: P_max (mean ± SE, runs) at each
    angle, and the ratio of the 6° cone's to the cylinder's where both were run (SE by
    propagation of the two SEs). Rows by law (rigid, spring, then creep), then by decreasing
    compliance; the state is per ladder file, named by its law and angle."""
    table = {}
    complete = {}
    for angle, path in ladders:
        path = Path(path)
        if not path.is_file():
            continue
        try:
            data = json.loads(path.read_text())
            laws = set()
            for setting, e in data["observables"]["P_max"].items():
                key = _ladder_compliance(setting)
                # A rung an earlier file gave (the rigid comparison's s0.01 runs are the spring
                # ladder's) is that file's, with its state.
                if key is None or e.get("mean") is None or angle in table.get(key, {}):
                    continue
                laws.add(key[0])
                table.setdefault(key, {})[angle] = (float(e["mean"]), e.get("se"), int(e["n"]))
            for law in laws:
                complete[(law, angle)] = data.get("complete", True)
        except (ValueError, KeyError, TypeError, AttributeError) as problem:
            raise PaperReproError(f"{path}: not a compare-settings comparison.json with observables.P_max "
                                  f"per setting ({type(problem).__name__}: {problem})") from None
    rows = []
    for law, eps in sorted(table, key=lambda k: (_LAW_RANK[k[0]], -k[1])):
        cells = table[(law, eps)]
        row = {"law": law, "eps": f"{eps:g}", "angles": {}, "ratio": "—"}
        for angle, (mean, se, n) in cells.items():
            row["angles"][angle] = f"{mean:.1f}" + (f" ± {se:.1f}" if se is not None else "") + f" ({n})"
        if 0.0 in cells and 6.0 in cells:
            (m0, s0, _), (m6, s6, _) = cells[0.0], cells[6.0]
            r = m6 / m0
            if s0 is not None and s6 is not None:
                row["ratio"] = f"{r:.2f} ± {r * math.hypot(s0 / m0, s6 / m6):.2f}"
            else:
                row["ratio"] = f"{r:.2f}"
        rows.append(row)
    ranked = sorted(complete, key=lambda k: (_LAW_RANK[k[0]], k[1]))
    return rows, {k: ("complete" if complete[k] else "partial") for k in ranked}


def _ladder_compliance(setting: str):
    """The law and compliance a ladder's setting names: 'e0.01' -> ('creep', 0.01),
    's0.01' -> ('spring', 0.01), 'rigid' -> ('rigid', 0.0); anything else (e.g.
    's0.01-ramp20') -> None."""
    if setting == _RIGID:
        return _RIGID, 0.0
    law = _LADDER_LAWS.get(setting[:1])
    if law is None:
        return None
    try:
        return law, float(setting[1:])
    except ValueError:
        return None


def _figures(analyses: dict, runs: Runs, statement: Statement, out: Path,
             drawn: dict) -> tuple[list, list]:
    paths, notes = [], []
    for part, name in statement.figures:
        a = analyses.get(part)
        if a is None:
            continue
        if (part, name) not in drawn:
            try:
                drawn[(part, name)] = FIGURES[name](a, out)
            except Exception as problem:  # a broken figure must not hide the verdicts
                traceback.print_exc(file=sys.stderr)
                drawn[(part, name)] = ([], [f"{a.case}: figure {name} failed: "
                                            f"{type(problem).__name__}: {problem}"])
            # The tier's caption speaks of the paper's 5 realizations; say what was there.
            planned = runs.plan.part_runs(_part(runs.plan, part))
            stored = sum(r.label in runs.used for r in planned)
            for path in drawn[(part, name)][0]:
                caption = Path(path).with_suffix(".txt")
                text = caption.read_text(encoding="utf-8").strip() if caption.is_file() else ""
                write_atomic(caption, f"{text} Drawn from {stored} of the {len(planned)} planned runs "
                                      f"of the campaign's part {part}"
                                      + (" (provisional)." if stored < len(planned) else ".") + "\n")
        made, why = drawn[(part, name)]
        paths += [str(p) for p in made]
        notes += why
    return paths, notes


def build(plan_path: Path = DEFAULT_PLAN, results: Path = DEFAULT_RESULTS, out: Path | None = None,
          reduced=(), ladders=LAW_LADDERS) -> dict:
    """The section's values: per statement the quote, checks, verdict, scale, what is
    missing, the reduced-scale rows and its figures (paths under OUT/figures/). `out`
    holds the assembled sweeps and the figures (rebuilt each time); `reduced` is a list
    of (source, headline record). Raises PaperReproError naming the file and field."""
    try:
        plan = load_plan(Path(plan_path))
    except PlanError as problem:
        raise PaperReproError(str(problem)) from None
    for name in _needed_parts():
        _part(plan, name)
    runs = survey(plan, Path(results))
    out = Path(out) if out is not None else REPO_ROOT / "out" / "paper-repro"
    figures_dir = out / "figures"
    if figures_dir.is_dir():  # no figure outlives its data
        for old in figures_dir.iterdir():
            if old.suffix in (".png", ".txt") and old.is_file():
                old.unlink()
    analyses = analyse(runs, out)
    drawn, statements = {}, []
    for statement in STATEMENTS:
        points = _points(plan, statement)
        scale = _scale(runs, points)
        params = []
        if statement.id == "table1":
            params, verdict, css = _table1(plan)
            scale = {**scale, "text": f"the scenes of the plan's {len(plan.runs)} runs; {scale['text']}"}
            rows = []
        else:
            rows = _check_rows(analyses, statement)
            verdict, css = _verdict(rows, scale)
        paths, notes = _figures(analyses, runs, statement, out, drawn)
        missing = _missing(runs, points)
        gap = statement.gap
        if set(statement.checks) & set(STAGE_CHECKS) and not store.KEEP.match(fields.STAGE_FILE):
            gap = "; ".join(filter(None, (gap, (
                f"the campaign does not store {fields.STAGE_FILE} (store.KEEP, "
                f"scripts/campaign_lib/store.py), which {', '.join(sorted(set(statement.checks) & set(STAGE_CHECKS)))} "
                "read: from the stored runs they are skipped until it does (the engine writes the "
                "file into the campaign's work folder)"))))
        reduced_rows = _reduced(statement, reduced)
        statements.append({
            "id": statement.id, "anchor": f"paper-{statement.id}", "figure": statement.figure,
            "topic": statement.topic, "quote": statement.quote,
            "check_ids": ", ".join(statement.checks) or "the plan's scene against Table 1",
            "gap": gap, "verdict": verdict, "verdict_class": css,
            "scale": scale["text"], "runs": f"{scale['stored']} of {scale['planned']}",
            "missing": missing, "checks": rows, "params": params,
            "reduced": reduced_rows, "reduced_summary": _reduced_summary(reduced_rows),
            "figures": paths, "notes": notes})
    planned = len(plan.runs)
    todo = planned - len(runs.used)
    todo_seconds, todo_source = runs.cost(list(plan.points))
    ladder_rows, ladder_state = _ladders(ladders)
    engines = sorted({str((s.provenance.get("engine") or {}).get("engine_commit"))[:10]
                      for s in runs.used.values()})
    return {
        "title": TITLE,
        "generated": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "plan": shown(plan.path), "results": shown(Path(results)),
        "stored": len(runs.used), "planned": planned,
        "parts": [{"name": p.name, "description": p.description,
                   "stored": sum(r.label in runs.used for r in plan.part_runs(p)),
                   "planned": len(plan.part_runs(p))} for p in plan.parts],
        "todo": (f"{todo} run(s), about {_hours(todo_seconds)} at {todo_source}"
                 if todo else "nothing: every planned run is stored"),
        "engines": engines, "refused": runs.refused, "statements": statements,
        "law": _law(plan), "ladders": ladder_rows,
        "ladder_state": ", ".join(f"{law} {a:g}° {st}" for (law, a), st in ladder_state.items()),
    }


# --------------------------------------------------------------------------- for templates


def with_figures(data: dict, figure) -> dict:
    """A copy of build()'s values whose figure paths are turned by `figure(path)` into
    what a template shows (a link, base64 data); the captions come with them."""
    statements = [{**s, "figures": [{"caption": figure_caption(Path(p)), **figure(Path(p))}
                                    for p in s["figures"]]} for s in data["statements"]]
    return {**data, "statements": statements}
