"""The two figures of one run folder (scripts/plot-run; the run read by ratchet.run_folder).

- results_figure: wall pressure against time with each cycle's peak and P_max, and the
  bed volume V/V0, from the start of cycling on; the thermal phases (heating, holds,
  cooling) as shading, the cycle numbers on a time axis above;
- solver_figure: kinetic energy, contacts, sweeps per step (the capped steps marked),
  residual, the largest overlap and the wall time per step over the whole run, the
  pour and settle shaded grey.

Axes are in the scene's scaled units (docs/method.md, "Units and scales"): time
sqrt(r_max/g), pressure ρ g r_max, energy ρ g r_max⁴, length r_max.
"""

from __future__ import annotations

import math
import os

os.environ.setdefault("MPLBACKEND", "Agg")

import matplotlib  # noqa: E402

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from .plots import MAX_LINE_POINTS, _thin  # noqa: E402
from common import paths  # noqa: F401,E402  (puts the package `ratchet` on sys.path)
from ratchet.run_folder import (DEFAULT_TOLERANCE, PHASES, THERMAL_DEFAULTS, TIME_COLUMNS,  # noqa: E402
                                Phase, Run, block_means, cycle_spans, cycle_stage_times, cycling_start,
                                thermal_phases)

#: Axis labels in the scene's scaled units, as docs/method.md states them; each panel's
#: title says what the quantity is.
TIME_LABEL = "time t / sqrt(r_max / g)"
PRESSURE_LABEL = "P / (ρ g r_max)"
VOLUME_LABEL = "V / V0"
ENERGY_LABEL = "E_kin / (ρ g r_max⁴)"
OVERLAP_LABEL = "overlap / r_max"
SWEEPS_LABEL = "sweeps per step"
RESIDUAL_LABEL = "residual"
CONTACTS_LABEL = "contacts (count)"
WALL_TIME_LABEL = "wall time (ms)"
#: Legends stand right of the panels, so that they never cover data.
LEGEND = {"fontsize": 7, "loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "borderaxespad": 0.0}
#: Shading of the phases (None: not shaded); the cold hold stays white.
PHASE_COLORS = {"heating": "#f6b48f", "hot hold": "#e4604e", "cooling": "#92c5de", "cold hold": None}
PHASE_ALPHA = 0.35
SOLVER_PHASE_ALPHA = 0.2  # lighter: the phases only place the diagnostics in the cycle
SETTLE_COLOR = "0.85"
#: The block-averaged pressure: dark orange, apart from P (C0) and the peaks (C3).
BLOCK_COLOR = "#d95f02"
#: The pressure axis reaches this multiple of the largest averaged pressure (or the 99.5th
#: percentile of P); single-step spikes above are cut and said so (_clip_spikes).
SPIKE_RANGE = 2.5
WIDTH = 11.0  # inches: 1320 px at 120 dpi, the panels and the legends beside them


def results_panels(run: Run) -> list[str]:
    """The panels of the results figure, top to bottom."""
    names = ["pressure"]
    has_volume = "V_over_V0" in run.ts.columns and run.ts["V_over_V0"].notna().any()
    if run.cycles is not None and len(run.cycles):
        has_volume |= bool(run.cycles[["V_over_V0_end_heating", "V_over_V0_end_cooling"]].notna().any().any())
    if has_volume:
        names.append("volume")
    return names


def solver_panels(run: Run) -> list[str]:
    """The panels of the solver figure, top to bottom."""
    names = ["kinetic_energy", "contacts", "iterations", "residual"]
    if "max_overlap" in run.ts.columns and run.ts["max_overlap"].notna().any():
        names.append("max_overlap")
    if any(c in run.ts.columns for c in TIME_COLUMNS):
        names.append("wall_time")
    return names


def describe(scene: dict, leave_out: tuple[str, ...] = ()) -> str:
    """What was run, in one line: particles, cone angle ("angle"), expansion ratio
    ("ratio"), cycles; leave_out names what a sweep varies."""
    parts = []
    generate = (scene.get("particles") or {}).get("generate") or {}
    if "count" in generate:
        shape = {"polyhedron": "polyhedra", "sphere": "spheres"}.get(generate.get("shape"), "particles")
        parts.append(f"{generate['count']} {shape}")
    container = scene.get("container") or {}
    if container.get("type") == "cone" and "angle" not in leave_out:
        parts.append(f"cone θ_c = {float(container.get('opening_angle_deg', 0)):g}°")
    th = scene.get("thermal")
    if isinstance(th, dict):
        th = {"alpha_p": 1e-4, "alpha_c": 1e-3, **THERMAL_DEFAULTS, **th}
        if th["alpha_p"] and "ratio" not in leave_out:
            parts.append(f"α_c/α_p = {th['alpha_c'] / th['alpha_p']:.3g}")
        parts.append(f"{th['cycles']} cycle{'s' if th['cycles'] != 1 else ''}")
    return ", ".join(parts)


def _panel_title(ax, text: str) -> None:
    ax.set_title(text, loc="left", fontsize=8, color="0.2", pad=3)


def _log_if_positive(ax, values: pd.Series) -> None:
    if (values > 0).any():
        ax.set_yscale("log", nonpositive="mask")  # zeros (no contact, state at rest) left out


def _shade(axes, phases: list[Phase], alpha: float = PHASE_ALPHA) -> None:
    for ax in axes:
        for p in phases:
            color = PHASE_COLORS[p.kind]
            if color is not None:
                ax.axvspan(p.start, p.end, color=color, alpha=alpha, lw=0, zorder=0)
        for first, _ in cycle_spans(phases).values():
            ax.axvline(first, color="0.55", lw=0.6, ls=":", zorder=1)


def _phase_handles(run: Run, alpha: float = PHASE_ALPHA) -> list[Patch]:
    th = run.scene.get("thermal")
    if isinstance(th, dict):
        th = {**THERMAL_DEFAULTS, **th}
        t0, t1 = f"T0 = {th['T0']:g}", f"T1 = {th['T1']:g}"
    else:
        t0, t1 = "T0", "T1"
    text = {"heating": "heating T0 → T1", "hot hold": f"hold at {t1}",
            "cooling": "cooling T1 → T0", "cold hold": f"hold at {t0} (white)"}
    return [Patch(facecolor=PHASE_COLORS[k] or "white", alpha=alpha if PHASE_COLORS[k] else 1,
                  edgecolor="0.6", label=text[k]) for k in PHASES]


def _cycle_axis(ax, phases: list[Phase]) -> None:
    """Cycle numbers (from 0, as cycles.csv) on a time axis above the panel."""
    spans = cycle_spans(phases)
    if not spans:
        return
    top = ax.secondary_xaxis("top")
    top.set_xticks([(a + b) / 2 for a, b in spans.values()], labels=[f"cycle {k}" for k in spans])
    top.tick_params(length=0, labelsize=8)


def _clip_spikes(ax, pressure: pd.Series, averaged: list[float]) -> None:
    """y from 0 to SPIKE_RANGE times the largest averaged pressure (block means, peaks,
    P_max), or to the 99.5th percentile of P when higher: single-step spikes far above
    would flatten the averaged pressure to the axis. What is cut is said on the panel."""
    values = pressure.to_numpy(dtype=float)
    values = values[np.isfinite(values)]
    averaged = [v for v in averaged if math.isfinite(v)]
    if not values.size or not averaged or max(averaged) <= 0:
        ax.set_ylim(bottom=0)
        return
    top = max(SPIKE_RANGE * max(averaged), float(np.quantile(values, 0.995)))
    if values.max() > 1.05 * top:
        ax.set_ylim(0, top)
        ax.text(0.995, 0.98, f"single steps reach P = {values.max():.3g} (off scale; "
                f"{int((values > top).sum())} rows)", transform=ax.transAxes, ha="right", va="top",
                fontsize=7, color="C0", bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8})
    else:
        ax.set_ylim(bottom=0)


def _block_steps(blocks: list[tuple[float, float, float]]) -> tuple[list[float], list[float]]:
    """A step line through the blocks (drawstyle steps-post), broken where blocks do not
    touch (the dropped end of a cycle)."""
    xs: list[float] = []
    ys: list[float] = []
    for i, (start, end, mean) in enumerate(blocks):
        if i and start != blocks[i - 1][1]:
            xs += [blocks[i - 1][1], blocks[i - 1][1]]
            ys += [blocks[i - 1][2], math.nan]
        xs.append(start)
        ys.append(mean)
    if blocks:
        xs.append(blocks[-1][1])
        ys.append(blocks[-1][2])
    return xs, ys


def _title(fig: Figure, run: Run, what: str) -> None:
    """The run's name and what the figure shows; below, the bed (or why the run is INCOMPLETE)."""
    fig.suptitle(f"{run.name}: {what}" + ("" if run.complete else " (INCOMPLETE)"), fontsize=11,
                 color="black" if run.complete else "C3", x=0.01, ha="left", y=0.995)
    sub = describe(run.scene) if run.complete else run.status
    if sub:
        fig.text(0.01, 0.995 - 0.28 / fig.get_figheight(), sub, ha="left", va="top", fontsize=8,
                 color="0.25" if run.complete else "C3")


def _footer(fig: Figure, handles: list[Patch], notes: list[str]) -> float:
    """The phase legend and the notes under the panels; returns the height they take (figure
    fraction)."""
    inch = 1.0 / fig.get_figheight()
    bottom = 0.0
    if notes:
        fig.text(0.01, 0.08 * inch, "\n".join(notes), fontsize=7, va="bottom", color="0.25",
                 linespacing=1.3)
        bottom += (0.08 + 0.14 * len(notes)) * inch
    if handles:
        fig.legend(handles=handles, loc="lower left", ncol=len(handles), fontsize=7, frameon=False,
                   bbox_to_anchor=(0.0, bottom), borderaxespad=0.3)
        bottom += 0.3 * inch
    return bottom


def results_figure(run: Run, phases: list[Phase] | None = None) -> Figure:
    """Wall pressure and V/V0 from the start of cycling, over the thermal phases."""
    phases = thermal_phases(run) if phases is None else phases
    names = results_panels(run)
    notes = list(run.notes)
    start = cycling_start(phases)
    ts = run.ts if start is None else run.ts[run.ts["t"] >= start - 1e-9]
    if start is not None and start > float(run.ts["t"].iloc[0]):
        notes.append(f"before cycling (t < {start:.4g}: pour and settle) not shown; "
                     f"the solver figure shows the whole run")
    lines = _thin(ts)
    if len(lines) < len(ts):
        notes.append(f"lines show one row in {int(np.ceil(len(ts) / MAX_LINE_POINTS))} of {len(ts)}")
    heights = [3, 2][:len(names)]
    fig = Figure(figsize=(WIDTH, 1.7 + 1.3 * sum(heights)))
    axes = dict(zip(names, fig.subplots(len(names), 1, sharex=True, squeeze=False,
                                        gridspec_kw={"height_ratios": heights})[:, 0]))
    _shade(axes.values(), phases)

    ax = axes["pressure"]
    _panel_title(ax, "side-wall pressure P(t)")
    every = run.row_steps
    ax.plot(lines["t"], lines["pressure"], color="C0", lw=0.6, alpha=0.75,
            label="P(t) of single steps" + (f"\n(a row every {every} steps)" if every != 1 else ""))
    blocks = block_means(run, phases)
    if blocks:
        xs, ys = _block_steps(blocks)
        ax.plot(xs, ys, drawstyle="steps-post", color=BLOCK_COLOR, lw=1.4, zorder=3,
                label=f"P averaged over blocks\nof Δt = {run.pressure_window:g} (outputs.\npressure_window)")
    elif phases and run.pressure_window > 0 and not run.every_step:
        notes.append(f"the block means of P are not drawn: they need a row per step "
                     f"(outputs.timeseries_every = 1; here a row every {every} steps)")
    if run.cycles is not None:
        peaks = run.cycles[np.isfinite(run.cycles["peak_pressure"])]
        ax.plot(peaks["t_peak"], peaks["peak_pressure"], "o", color="C3", ms=6, mec="black", mew=0.6,
                zorder=5, label=f"cycle peak: the largest\nblock mean of the cycle\n(Δt = {run.pressure_window:g}, "
                                "at its\nblock's middle)")
    if run.p_max is not None and math.isfinite(run.p_max):
        spans, steady = cycle_spans(phases), run.steady_cycles
        if steady is not None and steady[0] in spans and steady[1] in spans:
            x0, x1 = spans[steady[0]][0], spans[steady[1]][1]
            which = f"cycles {steady[0]}–{steady[1]}" if steady[1] > steady[0] else f"cycle {steady[0]}"
        else:
            x0, x1 = float(ts["t"].iloc[0]), float(ts["t"].iloc[-1])
            which = "the steady cycles"
        ax.hlines(run.p_max, x0, x1, color="black", ls="--", lw=1.1, zorder=4,
                  label=f"P_max = {run.p_max:.4g}:\nmean cycle peak of\n{which}")
    if not (ts["pressure"] != 0).any():
        notes.append("P is 0 on every row (a container without a cone's side wall: "
                     "docs/output-format.md, pressure)")
    ax.set_ylabel(PRESSURE_LABEL)
    _clip_spikes(ax, ts["pressure"], [m for _, _, m in blocks]
                 + ([] if run.cycles is None else list(run.cycles["peak_pressure"])) + [run.p_max or 0.0])
    ax.legend(**LEGEND)
    _cycle_axis(ax, phases)

    if "volume" in axes:
        ax = axes["volume"]
        _panel_title(ax, "bed volume V (convex hull) relative to V0, the settled bed before cycling")
        if "V_over_V0" in ts.columns and ts["V_over_V0"].notna().any():
            ax.plot(lines["t"], lines["V_over_V0"], color="0.25", lw=0.9, label="V/V0(t)")
        times = cycle_stage_times(run)
        if times is not None:
            for when, column, marker, color, text in (
                    (times[0], "V_over_V0_end_heating", "^", "C3", "end of heating"),
                    (times[1], "V_over_V0_end_cooling", "v", "C0", "end of cooling")):
                ax.plot(when, run.cycles[column], marker, color=color, ms=6, mec="black", mew=0.5,
                        zorder=5, label=text)
        elif run.cycles is not None:
            notes.append("V/V0 per cycle not drawn: the stage times are not in run.json")
        ax.set_ylabel(VOLUME_LABEL)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(**LEGEND)

    for ax in axes.values():
        ax.grid(alpha=0.3)
    axes[names[-1]].set_xlabel(TIME_LABEL)
    axes[names[-1]].set_xlim(float(ts["t"].iloc[0]), float(ts["t"].iloc[-1]))
    what = "wall pressure" + (" and bed volume" if "volume" in axes else "")
    _title(fig, run, what + (" over the thermal cycles" if phases else ""))
    bottom = _footer(fig, _phase_handles(run) if phases else [], notes)
    fig.tight_layout(rect=(0, bottom, 1, 1 - 0.3 / fig.get_figheight()), h_pad=0.6)
    return fig


def solver_figure(run: Run, phases: list[Phase] | None = None) -> Figure:
    """The solve over the whole run, pour and settle shaded grey, the thermal phases as in
    the results figure."""
    phases = thermal_phases(run) if phases is None else phases
    names = solver_panels(run)
    ts = run.ts
    lines = _thin(ts)
    notes = list(run.notes)
    if len(lines) < len(ts):
        notes.append(f"lines show one row in {int(np.ceil(len(ts) / MAX_LINE_POINTS))} of {len(ts)}; "
                     "the capped markers use every row")
    fig = Figure(figsize=(WIDTH, 1.45 * len(names) + 1.3))
    axes = dict(zip(names, fig.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0]))
    start = cycling_start(phases)
    t_first = float(ts["t"].iloc[0])
    settling = start is not None and start > t_first
    for ax in axes.values():
        if settling:
            ax.axvspan(t_first, start, color=SETTLE_COLOR, alpha=0.5, lw=0, zorder=0)
    _shade(axes.values(), phases, SOLVER_PHASE_ALPHA)
    t = lines["t"]
    mask = run.capped_mask

    ax = axes["kinetic_energy"]
    _panel_title(ax, "kinetic energy of the free bodies")
    ax.plot(t, lines["kinetic_energy"], color="C2", lw=0.7)
    _log_if_positive(ax, ts["kinetic_energy"])
    ax.set_ylabel(ENERGY_LABEL)
    _cycle_axis(ax, phases)

    ax = axes["contacts"]
    _panel_title(ax, "contact points with a positive normal impulse")
    ax.plot(t, lines["contacts"], color="C4", lw=0.7)
    ax.set_ylabel(CONTACTS_LABEL)

    ax = axes["iterations"]
    _panel_title(ax, "Gauss-Seidel sweeps of the step")
    ax.plot(t, lines["iterations"], color="C0", lw=0.7, label="sweeps")
    ax.set_ylabel(SWEEPS_LABEL)
    if mask is not None:
        if mask.any():
            ax.axhline(run.cap, color="C3", ls=":", lw=0.8)
            ax.plot(ts["t"][mask], ts["iterations"][mask], "x", color="C3", ms=5,
                    label=f"at the cap ({run.cap}):\n{int(mask.sum())} rows")
        else:
            ax.plot([], [], " ", label=f"no row at the\ncap ({run.cap} sweeps)")
    ax.legend(**LEGEND)

    ax = axes["residual"]
    solver = run.scene.get("solver") or {}
    criterion = solver.get("criterion", "impulse") if run.run is not None else None
    measure = {"impulse": ": ‖Δλ‖/‖λ‖", "velocity": ": sqrt(ΔE_sweep / E_contact)"}.get(criterion, "")
    _panel_title(ax, f"residual of the step's last sweep{measure} (dimensionless)")
    ax.plot(t, lines["residual"], color="C5", lw=0.7, label="residual")
    _log_if_positive(ax, ts["residual"])
    if run.run is not None:
        tol = float(solver.get("tolerance", DEFAULT_TOLERANCE))
        ax.axhline(tol, color="0.3", ls="--", lw=0.8, label=f"tolerance {tol:g}")
    if mask is not None and mask.any():
        ax.plot(ts["t"][mask], ts["residual"][mask], "x", color="C3", ms=5, label="at the cap")
    ax.set_ylabel(RESIDUAL_LABEL)
    ax.legend(**LEGEND)

    if "max_overlap" in axes:
        ax = axes["max_overlap"]
        _panel_title(ax, "largest overlap at the start of the step")
        ax.plot(t, lines["max_overlap"], color="C1", lw=0.7)
        _log_if_positive(ax, ts["max_overlap"])
        ax.set_ylabel(OVERLAP_LABEL)

    if "wall_time" in axes:
        ax = axes["wall_time"]
        _panel_title(ax, "wall-clock time of the step (time_* columns)")
        present = [c for c in TIME_COLUMNS if c in lines.columns]
        total = lines[present].sum(axis=1) * 1e3
        ax.plot(t, total, color="0.2", lw=0.7, label="whole step")
        for column, color in (("time_solve", "C0"), ("time_detect", "C1")):
            if column in lines.columns:
                ax.plot(t, lines[column] * 1e3, color=color, lw=0.6, alpha=0.8,
                        label=column.removeprefix("time_"))
        _log_if_positive(ax, total)
        ax.set_ylabel(WALL_TIME_LABEL)
        ax.legend(**LEGEND)

    for ax in axes.values():
        ax.grid(alpha=0.3)
    axes[names[-1]].set_xlabel(TIME_LABEL)
    axes[names[-1]].set_xlim(t_first, float(ts["t"].iloc[-1]))
    _title(fig, run, "solver diagnostics")
    handles = [Patch(facecolor=SETTLE_COLOR, alpha=0.5, label=f"pour and settle (t < {start:.4g})")] \
        if settling else []
    handles += _phase_handles(run, SOLVER_PHASE_ALPHA) if phases else []
    bottom = _footer(fig, handles, notes)
    fig.tight_layout(rect=(0, bottom, 1, 1 - 0.3 / fig.get_figheight()), h_pad=0.6)
    return fig
