"""The campaign plan: a JSON file naming the base scene, the points, the seeds and the
parts in the order they are run (format in docs/campaign.md, "The plan file").

Every error names the plan file and the field, before any work starts.
"""

from __future__ import annotations

import copy
import json
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from common.jsonc import load_json_with_comments
from common.paths import REPO_ROOT

#: Point and part names become folder names.
NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")
TOP_FIELDS = ("description", "scene", "set", "seeds", "run_cost_hours", "points", "parts")
POINT_FIELDS = ("name", "set", "seeds", "description")
PART_FIELDS = ("name", "description", "sweep", "points")


class PlanError(Exception):
    """A plan file that cannot be used; the message names the file and the field."""


@dataclass(frozen=True)
class Point:
    name: str
    set: dict
    seeds: tuple


@dataclass(frozen=True)
class Part:
    name: str
    description: str
    sweep: str
    points: tuple


@dataclass(frozen=True)
class Run:
    """One realization of one point: the unit that is run, stored and counted."""

    point: Point
    seed: int

    @property
    def label(self) -> str:
        return f"{self.point.name}/seed{self.seed}"


@dataclass
class Plan:
    path: Path
    name: str
    description: str
    scene_path: Path
    base_scene: dict
    set: dict
    points: dict                   # name -> Point, in file order
    parts: list
    run_cost_hours: float
    runs: list = field(default_factory=list)

    def scene_for(self, run: Run) -> dict:
        """The run's scene as the engine builds it from the one-run sweep file: the base
        scene, then the plan's `set` (sorted keys), then the point's (the sweep's grid,
        sorted keys), then the seed (docs/sweeps.md)."""
        scene = copy.deepcopy(self.base_scene)
        for key in sorted(self.set):
            apply_dotted(scene, key, self.set[key])
        for key in sorted(run.point.set):
            apply_dotted(scene, key, run.point.set[key])
        scene["seed"] = run.seed
        return scene

    def part_runs(self, part: Part) -> list:
        return [r for r in self.runs if r.point.name in part.points]


def apply_dotted(scene: dict, key: str, value) -> None:
    """Sets scene[a][b]... = value for key "a.b..."; missing objects are created, as the
    engine's --set and a sweep's `set` do."""
    parts = key.split(".")
    node = scene
    for part in parts[:-1]:
        if part not in node:
            node[part] = {}
        if not isinstance(node[part], dict):
            raise ValueError(f"'{part}' is inside a non-object")
        node = node[part]
    node[parts[-1]] = copy.deepcopy(value)


def same_json(a, b) -> bool:
    """Equality that also tells 1 from 1.0 from true: the engine's dump (and so the scene
    hash) differs between them."""
    if type(a) is not type(b):
        return False
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same_json(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(same_json(x, y) for x, y in zip(a, b))
    return a == b


def resolve(plan_arg: str) -> Path:
    """A plan name (validation/campaigns/<name>.json) or a path."""
    candidate = Path(plan_arg)
    if candidate.suffix == ".json" or candidate.exists() or "/" in plan_arg:
        return candidate
    return REPO_ROOT / "validation" / "campaigns" / f"{plan_arg}.json"


def _seeds(path, where, value) -> tuple:
    if (not isinstance(value, list) or not value
            or any(isinstance(s, bool) or not isinstance(s, int) or s < 0 for s in value)):
        raise PlanError(f"{path}: field '{where}': expected a non-empty list of integers >= 0, got {json.dumps(value)}")
    if len(set(value)) != len(value):
        raise PlanError(f"{path}: field '{where}': a seed is listed twice: {json.dumps(value)}")
    return tuple(value)


def _set(path, where, value) -> dict:
    if not isinstance(value, dict):
        raise PlanError(f"{path}: field '{where}': expected an object {{\"dotted.path\": value}}, got {json.dumps(value)}")
    for key in value:
        if not key or any(not p for p in key.split(".")):
            raise PlanError(f"{path}: field '{where}': '{key}' is not a dotted scene path (empty part)")
        if key == "seed":
            raise PlanError(f"{path}: field '{where}.seed': the seed comes from 'seeds', not from 'set'")
    return value


def _unknown(path, where, obj, known):
    for key in obj:
        if key not in known:
            prefix = f"{where}." if where else ""
            raise PlanError(f"{path}: field '{prefix}{key}': unknown field (known fields here: {', '.join(known)})")


def load_plan(plan_path: Path) -> Plan:
    path = Path(plan_path)
    try:
        data = load_json_with_comments(path)
    except OSError as error:
        raise PlanError(f"{path}: cannot read the plan file ({error.strerror or error})") from None
    except ValueError as error:
        raise PlanError(f"{path}: not valid JSON ({error})") from None
    if not isinstance(data, dict):
        raise PlanError(f"{path}: expected a JSON object (the campaign plan)")
    _unknown(path, "", data, TOP_FIELDS)
    for required in ("scene", "seeds", "points", "parts", "run_cost_hours"):
        if required not in data:
            raise PlanError(f"{path}: field '{required}': missing (required; docs/campaign.md)")

    if not isinstance(data["scene"], str) or not data["scene"]:
        raise PlanError(f"{path}: field 'scene': expected a scene file path relative to the plan's folder, "
                        f"got {json.dumps(data['scene'])}")
    scene_path = (path.parent / data["scene"]).resolve()
    try:
        base_scene = load_json_with_comments(scene_path)
    except OSError as error:
        raise PlanError(f"{path}: field 'scene': cannot read {scene_path} ({error.strerror or error})") from None
    except ValueError as error:
        raise PlanError(f"{path}: field 'scene': {scene_path} is not valid JSON ({error})") from None
    if not isinstance(base_scene, dict):
        raise PlanError(f"{path}: field 'scene': {scene_path} is not a JSON object (a scene)")

    cost = data["run_cost_hours"]
    if isinstance(cost, bool) or not isinstance(cost, (int, float)) or not math.isfinite(cost) or cost <= 0:
        raise PlanError(f"{path}: field 'run_cost_hours': expected a number > 0 (the estimated hours of one run "
                        f"before any is measured), got {json.dumps(cost)}")
    seeds = _seeds(path, "seeds", data["seeds"])
    common_set = _set(path, "set", data.get("set", {}))

    points = {}
    if not isinstance(data["points"], list) or not data["points"]:
        raise PlanError(f"{path}: field 'points': expected a non-empty list of points")
    for i, raw in enumerate(data["points"]):
        where = f"points[{i}]"
        if not isinstance(raw, dict):
            raise PlanError(f"{path}: field '{where}': expected an object {{\"name\", \"set\"}}, got {json.dumps(raw)}")
        _unknown(path, where, raw, POINT_FIELDS)
        name = raw.get("name")
        if not isinstance(name, str) or not NAME.match(name):
            raise PlanError(f"{path}: field '{where}.name': expected a name of letters, digits, '.', '_' or '-' "
                            f"(it names a folder), got {json.dumps(name)}")
        if name in points:
            raise PlanError(f"{path}: field '{where}.name': point '{name}' is defined twice")
        if "set" not in raw:
            raise PlanError(f"{path}: field '{where}.set': missing (required: the scene fields of this point)")
        point_set = _set(path, f"{where}.set", raw["set"])
        point_seeds = _seeds(path, f"{where}.seeds", raw["seeds"]) if "seeds" in raw else seeds
        points[name] = Point(name=name, set=point_set, seeds=point_seeds)

    parts = []
    if not isinstance(data["parts"], list) or not data["parts"]:
        raise PlanError(f"{path}: field 'parts': expected a non-empty list of parts")
    for i, raw in enumerate(data["parts"]):
        where = f"parts[{i}]"
        if not isinstance(raw, dict):
            raise PlanError(f"{path}: field '{where}': expected an object {{\"name\", \"sweep\", \"points\"}}")
        _unknown(path, where, raw, PART_FIELDS)
        name = raw.get("name")
        if not isinstance(name, str) or not NAME.match(name):
            raise PlanError(f"{path}: field '{where}.name': expected a name of letters, digits, '.', '_' or '-', "
                            f"got {json.dumps(name)}")
        if any(p.name == name for p in parts):
            raise PlanError(f"{path}: field '{where}.name': part '{name}' is defined twice")
        members = raw.get("points")
        if not isinstance(members, list) or not members or not all(isinstance(m, str) for m in members):
            raise PlanError(f"{path}: field '{where}.points': expected a non-empty list of point names")
        for j, member in enumerate(members):
            if member not in points:
                raise PlanError(f"{path}: field '{where}.points[{j}]': no point named '{member}' in 'points'")
        sweep = raw.get("sweep")
        if not isinstance(sweep, str) or not sweep:
            raise PlanError(f"{path}: field '{where}.sweep': expected the dotted scene path this part sweeps "
                            f"(the column of its summary.csv), got {json.dumps(sweep)}")
        for j, member in enumerate(members):
            if sweep not in points[member].set:
                raise PlanError(f"{path}: field '{where}.sweep': point '{member}' does not set '{sweep}'")
        parts.append(Part(name=name, description=str(raw.get("description", "")), sweep=sweep,
                          points=tuple(members)))
    unused = [n for n in points if not any(n in p.points for p in parts)]
    if unused:
        raise PlanError(f"{path}: field 'points': point(s) {', '.join(unused)} belong to no part (never run)")

    plan = Plan(path=path, name=path.stem, description=str(data.get("description", "")), scene_path=scene_path,
                base_scene=base_scene, set=common_set, points=points, parts=parts,
                run_cost_hours=float(cost))
    # Plan order: parts in order; within a part seed by seed across its points, so that a
    # part cut short has its points equally far; a run shared with an earlier part once.
    seen = set()
    for part in parts:
        members = [points[n] for n in part.points]
        depth = max(len(p.seeds) for p in members)
        for k in range(depth):
            for point in members:
                if k < len(point.seeds) and (point.name, point.seeds[k]) not in seen:
                    seen.add((point.name, point.seeds[k]))
                    plan.runs.append(Run(point=point, seed=point.seeds[k]))
    for run in plan.runs:
        try:
            plan.scene_for(run)
        except ValueError as error:
            raise PlanError(f"{path}: field 'points' ('{run.point.name}'): cannot apply its 'set' to "
                            f"{scene_path.name}: {error}") from None
    return plan
