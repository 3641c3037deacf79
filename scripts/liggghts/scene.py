"""Reading a ratchet scene for the LIGGGHTS translation.

The engine's parser (reference_engine/src/ratchet/scene/, scene.cpp and its parts) is the authority.
The bodies, generated or listed, come from the engine itself: `ratchet bodies SCENE
--out FILE` builds the scene exactly as `ratchet run` does and writes every body
(docs/output-format.md, "Bodies and shapes"); nothing is regenerated here. This module
reads the settings a sphere scene's deck needs (time, materials, effects, container,
thermal protocol), with the engine's defaults. What the translation cannot carry
(polyhedra, boxes, a settle section) is refused with a message naming the file and
the field.
"""

import json
import math
import os
import subprocess
import tempfile
from dataclasses import dataclass, field
from typing import List, Optional

from common.jsonc import loads_json_with_comments
from common import paths  # noqa: F401  (puts this checkout's package `ratchet` on sys.path)
from ratchet import ProgramNotFound, command, program

BODIES_FORMAT = "ratchet-bodies"
BODIES_VERSION = 1


class SceneError(ValueError):
    """A scene that cannot be read or translated; the message names file and field."""


class EngineError(RuntimeError):
    """The engine binary is missing, or failed on a scene it accepted."""


@dataclass
class Wall:
    normal: tuple          # unit inward normal
    point: tuple           # a point of the plane at container scale 1
    role: str              # "bottom", "side" or "plane"
    expands: bool


@dataclass
class Sphere:
    position: tuple
    radius: float
    velocity: tuple = (0.0, 0.0, 0.0)
    angular_velocity: tuple = (0.0, 0.0, 0.0)
    fixed: bool = False


@dataclass
class Thermal:
    T0: float = 0.0
    T1: float = 100.0
    start_time: float = 0.0
    heat_time: float = 1.0
    hold_time: float = 0.0
    cool_time: float = 1.0
    cycles: int = 1
    alpha_p: float = 1e-4
    alpha_c: float = 1e-3

    @property
    def cycle_time(self):
        return self.heat_time + self.hold_time + self.cool_time + self.hold_time

    def temperature(self, t):
        """T(t) as the engine defines it (docs/scene-format.md, `thermal`)."""
        tau = t - self.start_time
        if tau <= 0.0 or tau >= self.cycles * self.cycle_time:
            return self.T0
        tp = math.fmod(tau, self.cycle_time)
        if tp < self.heat_time:
            return self.T0 + (self.T1 - self.T0) * tp / self.heat_time
        tp -= self.heat_time
        if tp < self.hold_time:
            return self.T1
        tp -= self.hold_time
        if tp < self.cool_time:
            return self.T1 + (self.T0 - self.T1) * tp / self.cool_time
        return self.T0


@dataclass
class Scene:
    source: str
    name: str
    seed: int
    gravity: tuple
    dt: float
    duration: float
    friction: float
    wall_friction: float
    density: float
    effects: dict
    container_type: Optional[str]          # "cone", "planes" or None
    bottom_radius: float = 8.5
    opening_angle_deg: float = 0.0
    segments: int = 16
    height: float = 30.0
    walls: List[Wall] = field(default_factory=list)
    spheres: List[Sphere] = field(default_factory=list)
    thermal: Optional[Thermal] = None
    timeseries_every: int = 1
    raw: dict = field(default_factory=dict)
    bodies_file: Optional[dict] = None     # the document `ratchet bodies` wrote (load_scene)

    @property
    def steps(self):
        return int(round_half_away(self.duration / self.dt))

    @property
    def theta(self):
        return math.radians(self.opening_angle_deg)

    def particle_expansion_on(self):
        return self.thermal is not None and self.effects["particle_expansion"]

    def container_expansion_on(self):
        return self.thermal is not None and self.effects["container_expansion"]

    def stages(self):
        """The thermal protocol as a list of stages (kind, t_begin, t_end, T_begin, T_end),
        kind in settle/heat/hold/cool/rest, covering [0, duration]."""
        end = self.steps * self.dt
        if self.thermal is None:
            return [("settle", 0.0, end, 0.0, 0.0)]
        th = self.thermal
        out = []
        t = 0.0
        if th.start_time > 0.0:
            out.append(("settle", 0.0, th.start_time, th.T0, th.T0))
            t = th.start_time
        for _ in range(th.cycles):
            for kind, d, Ta, Tb in (("heat", th.heat_time, th.T0, th.T1), ("hold", th.hold_time, th.T1, th.T1),
                                    ("cool", th.cool_time, th.T1, th.T0), ("hold", th.hold_time, th.T0, th.T0)):
                if d > 0.0:
                    out.append((kind, t, t + d, Ta, Tb))
                    t += d
        out.append(("rest", t, max(t, end), th.T0, th.T0))
        # Cut at the end of the run (the duration may be shorter than the protocol).
        cut = []
        for kind, a, b, Ta, Tb in out:
            if a >= end - 1e-12 * max(1.0, end):
                break
            if b > end:
                Tb = Ta + (Tb - Ta) * (end - a) / (b - a)
                b = end
            if b > a:
                cut.append((kind, a, b, Ta, Tb))
        return cut

    def cycle_windows(self):
        """[(cycle index, t_begin, t_end)] of the thermal cycles within the run."""
        if self.thermal is None:
            return []
        th = self.thermal
        end = self.steps * self.dt
        out = []
        for c in range(th.cycles):
            a = th.start_time + c * th.cycle_time
            b = a + th.cycle_time
            if a >= end:
                break
            out.append((c, a, min(b, end)))
        return out


def round_half_away(x):
    """std::llround: halves away from zero."""
    return math.floor(x + 0.5) if x >= 0 else -math.floor(-x + 0.5)


class _Reader:
    def __init__(self, source):
        self.source = source

    def fail(self, field_name, expected, got=None):
        msg = f"{self.source}: field '{field_name}': expected {expected}"
        if got is not None:
            shown = json.dumps(got)
            if len(shown) > 80:
                shown = shown[:77] + "..."
            msg += f", got {shown}"
        raise SceneError(msg)

    def obj(self, j, path, used):
        """Checks that `j` is an object. Fields other than `used` are not checked here:
        the engine's parser is the authority on the full format (compare-methods runs
        `ratchet run --explain` first), and it grows new fields."""
        if not isinstance(j, dict):
            self.fail(path or "(top level)", "an object", j)

    def num(self, j, path, key, default, lo=-math.inf, hi=math.inf, lo_open=False, hi_open=False,
            expected="a finite number"):
        if key not in j:
            return default
        v = j[key]
        f = f"{path}.{key}" if path else key
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            self.fail(f, expected, v)
        x = float(v)
        ok = math.isfinite(x) and (x > lo if lo_open else x >= lo) and (x < hi if hi_open else x <= hi)
        if not ok:
            self.fail(f, expected, v)
        return x

    def pos(self, j, path, key, default):
        return self.num(j, path, key, default, 0.0, math.inf, True, False, "a finite positive number")

    def nonneg(self, j, path, key, default):
        return self.num(j, path, key, default, 0.0, math.inf, False, False, "a finite number >= 0")

    def integer(self, j, path, key, default, lo, hi):
        if key not in j:
            return default
        v = j[key]
        f = f"{path}.{key}" if path else key
        if isinstance(v, bool) or not isinstance(v, int) or v < lo or v > hi:
            self.fail(f, f"an integer in [{lo}, {hi}]", v)
        return v

    def boolean(self, j, path, key, default):
        if key not in j:
            return default
        v = j[key]
        if not isinstance(v, bool):
            self.fail(f"{path}.{key}", "true or false", v)
        return v

    def vec3(self, v, f):
        if not isinstance(v, list) or len(v) != 3 or any(
                isinstance(a, bool) or not isinstance(a, (int, float)) or not math.isfinite(a) for a in v):
            self.fail(f, "an array of 3 finite numbers", v)
        return tuple(float(a) for a in v)

    def required(self, j, path, key, expected):
        if key not in j:
            self.fail(f"{path}.{key}" if path else key, expected + " (the field is required)")
        return j[key]


def _normalize(v):
    n = math.sqrt(sum(a * a for a in v))
    return tuple(a / n for a in v)


def cone_walls(bottom_radius, opening_angle_deg, segments):
    """Floor plus N side segments exactly as build_cone_walls in scene_sections.cpp."""
    th = math.radians(opening_angle_deg)
    walls = [Wall((0.0, 0.0, 1.0), (0.0, 0.0, 0.0), "bottom", True)]
    for k in range(segments):
        phi = 2.0 * math.pi * k / segments
        n = (-math.cos(th) * math.cos(phi), -math.cos(th) * math.sin(phi), math.sin(th))
        p = (bottom_radius * math.cos(phi), bottom_radius * math.sin(phi), 0.0)
        walls.append(Wall(n, p, "side", True))
    return walls


def engine_bodies(path, ratchet=None):
    """The engine's bodies of the scene file `path`: runs `ratchet bodies PATH --out
    TMP --quiet` and returns the document it wrote. `ratchet`: the binary (default the
    build's, ratchet.program(): $RATCHET_BIN, else <$RATCHET_BUILD_DIR or
    build>/reference_engine/ratchet). A scene the engine refuses raises SceneError with
    the engine's message (it names the file and the field); a missing binary or another
    failure raises EngineError."""
    try:
        ratchet = str(program(ratchet))
    except ProgramNotFound as e:
        raise EngineError(f"engine binary not found or not executable: {e.filename} (build it, or set "
                          "RATCHET_BUILD_DIR or RATCHET_BIN): the translation takes the bodies from `ratchet bodies`") \
            from None
    with tempfile.TemporaryDirectory(prefix="ratchet_bodies_") as tmp:
        out = os.path.join(tmp, "bodies.json")
        r = subprocess.run(command("bodies", path, "--out", out, "--quiet", ratchet=ratchet), capture_output=True,
                           text=True)
        msg = (r.stderr or r.stdout).strip()
        if msg.startswith("ratchet: error: "):
            msg = msg[len("ratchet: error: "):]
        if r.returncode == 2:
            raise SceneError(msg)
        if r.returncode != 0:
            raise EngineError(f"{ratchet} bodies {path} failed (exit {r.returncode}): {msg}")
        try:
            with open(out, "r", encoding="utf-8") as fh:
                doc = json.load(fh)
        except (OSError, ValueError) as e:
            raise EngineError(f"{ratchet} bodies {path}: cannot read the bodies file it wrote: {e}") from None
    if doc.get("format") != BODIES_FORMAT or doc.get("version") != BODIES_VERSION:
        raise EngineError(f"{ratchet} bodies {path}: bodies file format {doc.get('format')!r} version "
                          f"{doc.get('version')!r}; this translator reads {BODIES_FORMAT!r} version {BODIES_VERSION}")
    return doc


def spheres_from_bodies(doc, j, source):
    """The spheres of an engine bodies document, in body order. A polyhedron (generated
    polyhedra, listed boxes and polyhedra) is refused naming the scene field it came
    from: generated bodies come first, then the listed ones in list order."""
    parts = j.get("particles", {}) if isinstance(j, dict) else {}
    gen = parts.get("generate", {}) if isinstance(parts, dict) else {}
    n_gen = gen.get("count", 0) if isinstance(gen, dict) else 0
    listed = parts.get("bodies", []) if isinstance(parts, dict) else []
    out = []
    for b in doc["bodies"]:
        if b["kind"] != "sphere":
            i = b["index"]
            if i < n_gen:
                raise SceneError(f"{source}: field 'particles.generate.shape': expected \"sphere\" (the LIGGGHTS "
                                 "translation handles spheres only; polyhedra have no counterpart in this soft-sphere "
                                 f"DEM), got {json.dumps(gen.get('shape', 'polyhedron'))}")
            k = i - n_gen
            got = listed[k].get("shape") if 0 <= k < len(listed) and isinstance(listed[k], dict) else b["kind"]
            raise SceneError(f"{source}: field 'particles.bodies[{k}].shape': expected \"sphere\" (the LIGGGHTS "
                             f"translation handles spheres only), got {json.dumps(got)}")
        out.append(Sphere(position=tuple(float(c) for c in b["position"]), radius=float(b["radius"]),
                          velocity=tuple(float(c) for c in b["velocity"]),
                          angular_velocity=tuple(float(c) for c in b["angular_velocity"]),
                          fixed=bool(b["fixed"])))
    return out


def load_scene(path, ratchet=None):
    """Reads and checks a scene file; returns a Scene with every sphere, as the engine
    built them (`ratchet bodies`, see engine_bodies)."""
    try:
        with open(path, "r", encoding="utf-8") as fh:
            text = fh.read()
    except OSError as e:
        raise SceneError(f"{path}: cannot open the scene file ({e.strerror})") from None
    try:
        j = loads_json_with_comments(text)
    except ValueError as e:
        raise SceneError(f"{path}: not valid JSON: {e}") from None
    sc = build_scene(j, path)
    sc.bodies_file = engine_bodies(path, ratchet)
    sc.spheres = spheres_from_bodies(sc.bodies_file, j, path)
    return sc


def build_scene(j, source):
    """The settings of a scene (JSON already parsed), checked; no bodies (load_scene
    adds the engine's)."""
    r = _Reader(source)
    r.obj(j, "", ["name", "seed", "gravity", "time", "solver", "materials", "effects", "container",
                  "particles", "thermal", "outputs", "description"])
    name = j.get("name", "")
    if not isinstance(name, str) or not name:
        r.fail("name", "a non-empty string", j.get("name"))
    if "settle" in j:
        # A settle section ends the settle stage when the engine's bed comes to rest, a
        # time the deck cannot know in advance; the deck needs thermal.start_time.
        r.fail("settle", "no settle section in a scene for LIGGGHTS (the deck's thermal schedule is fixed "
               "in advance: set thermal.start_time instead)", j["settle"])
    seed = r.integer(j, "", "seed", 1, 0, 2 ** 63 - 1)
    gravity = r.vec3(j["gravity"], "gravity") if "gravity" in j else (0.0, 0.0, -1.0)
    effects = dict(gravity=True, friction=True, rotation=True, particle_expansion=True, container_expansion=True)
    if "effects" in j:
        r.obj(j["effects"], "effects", list(effects))
        for k in effects:
            effects[k] = r.boolean(j["effects"], "effects", k, effects[k])
    friction, wall_friction, density = 0.5, 0.5, 1.0
    if "materials" in j:
        m = j["materials"]
        r.obj(m, "materials", ["friction", "wall_friction", "density"])
        friction = r.nonneg(m, "materials", "friction", friction)
        wall_friction = r.nonneg(m, "materials", "wall_friction", wall_friction)
        density = r.pos(m, "materials", "density", density)
    thermal = None
    if "thermal" in j:
        t = j["thermal"]
        p = "thermal"
        r.obj(t, p, ["T0", "T1", "start_time", "heat_time", "hold_time", "cool_time", "cycles", "alpha_p",
                     "alpha_c"])
        th = Thermal()
        th.T0 = r.num(t, p, "T0", th.T0)
        th.T1 = r.num(t, p, "T1", th.T1)
        th.start_time = r.nonneg(t, p, "start_time", 0.0)
        th.heat_time = r.pos(t, p, "heat_time", 1.0)
        th.hold_time = r.nonneg(t, p, "hold_time", 0.0)
        th.cool_time = r.pos(t, p, "cool_time", th.heat_time)
        th.cycles = r.integer(t, p, "cycles", 1, 0, 1000000)
        th.alpha_p = r.num(t, p, "alpha_p", th.alpha_p)
        th.alpha_c = r.num(t, p, "alpha_c", th.alpha_c)
        for a in (th.alpha_p, th.alpha_c):
            if 1.0 + a * (th.T1 - th.T0) <= 0.0:
                r.fail("thermal.alpha_p/alpha_c", "1 + alpha (T1 - T0) > 0 (a scale factor cannot vanish)")
        thermal = th
    sc = Scene(source=source, name=name, seed=seed, gravity=gravity, dt=0.001, duration=0.0, friction=friction,
               wall_friction=wall_friction, density=density, effects=effects, container_type=None,
               thermal=thermal, raw=j)
    if "container" in j:
        c = j["container"]
        p = "container"
        if not isinstance(c, dict):
            r.fail(p, "an object", c)
        ctype = c.get("type", "")
        if ctype == "cone":
            r.obj(c, p, ["type", "bottom_radius", "opening_angle_deg", "segments", "height"])
            sc.container_type = "cone"
            sc.bottom_radius = r.pos(c, p, "bottom_radius", 8.5)
            sc.opening_angle_deg = r.num(c, p, "opening_angle_deg", 0.0, 0.0, 45.0, False, False,
                                         "an angle in degrees in [0, 45]")
            sc.segments = r.integer(c, p, "segments", 16, 3, 1024)
            sc.height = r.pos(c, p, "height", 30.0)
            sc.walls = cone_walls(sc.bottom_radius, sc.opening_angle_deg, sc.segments)
        elif ctype == "planes":
            r.obj(c, p, ["type", "planes"])
            sc.container_type = "planes"
            planes = r.required(c, p, "planes", "a list of {normal, point}")
            if not isinstance(planes, list) or not planes:
                r.fail(p + ".planes", "a non-empty list of {normal, point}", planes)
            for i, pl in enumerate(planes):
                f = f"{p}.planes[{i}]"
                r.obj(pl, f, ["normal", "point", "expands"])
                n = r.vec3(r.required(pl, f, "normal", "a vector [x, y, z]"), f + ".normal")
                if math.sqrt(sum(a * a for a in n)) < 1e-12:
                    r.fail(f + ".normal", "a non-zero vector", pl["normal"])
                pt = r.vec3(r.required(pl, f, "point", "a point [x, y, z]"), f + ".point")
                sc.walls.append(Wall(_normalize(n), pt, "plane", r.boolean(pl, f, "expands", False)))
        else:
            r.fail(p + ".type", "\"cone\" or \"planes\"", c.get("type"))
    if "outputs" in j:
        r.obj(j["outputs"], "outputs", ["timeseries_every", "bodies_every"])
        sc.timeseries_every = r.integer(j["outputs"], "outputs", "timeseries_every", 1, 1, 1 << 30)
    time = r.required(j, "", "time", "an object {dt, duration}")
    r.obj(time, "time", ["dt", "duration"])
    sc.dt = r.pos(time, "time", "dt", 0.001)
    if "duration" in time:
        sc.duration = r.pos(time, "time", "duration", 0.0)
    elif thermal is not None and thermal.cycles > 0:
        sc.duration = thermal.start_time + thermal.cycles * thermal.cycle_time
    else:
        r.fail("time.duration", "a positive duration (or a thermal protocol with cycles to derive it from)")
    if sc.steps < 1:
        r.fail("time.duration", "at least one time step (duration >= dt)", time.get("duration"))
    parts = r.required(j, "", "particles", "an object {generate and/or bodies}")
    r.obj(parts, "particles", ["generate", "bodies"])
    return sc
