"""Reading a ratchet scene for the LIGGGHTS translation.

The engine's parser (reference_engine/src/ratchet/scene/scene.cpp) is the authority;
this module reads the subset that a sphere scene needs, with the same defaults, and
reproduces the generated particles exactly (same std::mt19937_64 draws, same lattice
arithmetic; the engine is compiled with -ffp-contract=off, so Python doubles give the
same numbers). What the translation cannot carry (polyhedra, boxes) is refused with
a message naming the file and the field.
"""

import json
import math
from dataclasses import dataclass, field
from typing import List, Optional

from common.jsonc import loads_json_with_comments

from .mt19937_64 import MT19937_64, uniform


class SceneError(ValueError):
    """A scene that cannot be read or translated; the message names file and field."""


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
    """Floor plus N side segments exactly as build_cone_walls in scene.cpp."""
    th = math.radians(opening_angle_deg)
    walls = [Wall((0.0, 0.0, 1.0), (0.0, 0.0, 0.0), "bottom", True)]
    for k in range(segments):
        phi = 2.0 * math.pi * k / segments
        n = (-math.cos(th) * math.cos(phi), -math.cos(th) * math.sin(phi), math.sin(th))
        p = (bottom_radius * math.cos(phi), bottom_radius * math.sin(phi), 0.0)
        walls.append(Wall(n, p, "side", True))
    return walls


def _lattice_sites(r, sc, gen, spacing, count, rng):
    """lattice_sites() of scene.cpp, same loop arithmetic and draw order: a square
    lattice in x, y (centred on the axis for a cone, from the corner for a region box),
    layers from the bottom, each site jittered in x and y by up to 0.04 spacing."""
    in_disk = False
    disk_radius = 0.0
    if "region" in gen:
        f = "particles.generate.region"
        reg = gen["region"]
        if not isinstance(reg, dict):
            r.fail(f, "an object {min, max}", reg)
        lo = r.vec3(r.required(reg, f, "min", "a point [x, y, z]"), f + ".min")
        hi = r.vec3(r.required(reg, f, "max", "a point [x, y, z]"), f + ".max")
        if not all(h - l > 0.0 for l, h in zip(lo, hi)):
            r.fail(f, "min < max in every coordinate", reg)
    elif sc.container_type == "cone":
        in_disk = True
        disk_radius = sc.bottom_radius - 0.5 * spacing - 0.04 * spacing
        lo = (-disk_radius, -disk_radius, 0.0)
        hi = (disk_radius, disk_radius, math.inf)
    else:
        r.fail("particles.generate.region", "a region {min, max} (required unless the container is a cone)")
    sites = []
    jitter = 0.04 * spacing
    origin = (0.0, 0.0, lo[2]) if in_disk else (lo[0] + 0.5 * spacing, lo[1] + 0.5 * spacing, lo[2])
    kx_lo = -int(math.floor(disk_radius / spacing)) if in_disk else 0
    kx_hi = -kx_lo if in_disk else int(math.floor((hi[0] - lo[0]) / spacing)) - 1
    ky_hi = -kx_lo if in_disk else int(math.floor((hi[1] - lo[1]) / spacing)) - 1
    layer = 0
    while len(sites) < count and layer < 1000000:
        z = origin[2] + 0.5 * spacing + layer * spacing
        if z + 0.5 * spacing > hi[2]:
            break
        for ky in range(kx_lo, ky_hi + 1):
            for kx in range(kx_lo, kx_hi + 1):
                x = origin[0] + kx * spacing
                y = origin[1] + ky * spacing
                if in_disk and math.hypot(x, y) > disk_radius:
                    continue
                if len(sites) >= count:
                    break
                # emplace_back(x + uniform(..), y + uniform(..), z): GCC evaluates these
                # arguments right to left, so the y jitter is drawn first (checked against
                # the engine's bodies.csv by compare-methods and the tests).
                jy = uniform(rng, -jitter, jitter)
                jx = uniform(rng, -jitter, jitter)
                sites.append((x + jx, y + jy, z))
        layer += 1
    if len(sites) < count:
        r.fail("particles.generate.count",
               f"at most {len(sites)} particles (that is what fits in the region at lattice spacing {spacing:f})",
               gen.get("count"))
    return sites


def _generated_spheres(r, sc, gen, rng):
    p = "particles.generate"
    r.obj(gen, p, ["count", "shape", "vertices", "ellipsoid_axes", "radius_range", "region", "spacing"])
    count = r.integer(gen, p, "count", 0, 0, 10000000)
    shape = gen.get("shape", "polyhedron")
    if shape not in ("polyhedron", "sphere"):
        r.fail(p + ".shape", "\"polyhedron\" or \"sphere\"", shape)
    rmin, rmax = 0.5, 1.0
    if "radius_range" in gen:
        rr = gen["radius_range"]
        if (not isinstance(rr, list) or len(rr) != 2 or any(isinstance(a, bool) or not isinstance(a, (int, float))
                                                            for a in rr)
                or not rr[0] > 0.0 or not rr[1] >= rr[0] or not math.isfinite(rr[1])):
            r.fail(p + ".radius_range", "[r_min, r_max] with 0 < r_min <= r_max", rr)
        rmin, rmax = float(rr[0]), float(rr[1])
    spacing = r.num(gen, p, "spacing", 2.5 * rmax, 2.3 * rmax, math.inf, False, False,
                    "a lattice spacing >= 2.3 r_max (sites must not overlap)")
    if count > 0 and shape != "sphere":
        r.fail(p + ".shape", "\"sphere\" (the LIGGGHTS translation handles spheres only; "
               "polyhedra have no counterpart in this soft-sphere DEM)", shape)
    sites = _lattice_sites(r, sc, gen, spacing, count, rng)
    out = []
    for i in range(count):
        radius = uniform(rng, rmin, rmax)
        out.append(Sphere(position=sites[i], radius=radius))
    return out


def _listed_spheres(r, lst):
    if not isinstance(lst, list):
        r.fail("particles.bodies", "a list of bodies", lst)
    out = []
    for i, j in enumerate(lst):
        f = f"particles.bodies[{i}]"
        r.obj(j, f, ["shape", "radius", "half_extents", "vertices", "position", "orientation", "velocity",
                     "angular_velocity", "fixed"])
        shape = j.get("shape", "")
        if shape != "sphere":
            r.fail(f + ".shape", "\"sphere\" (the LIGGGHTS translation handles spheres only)", shape)
        pos = r.vec3(r.required(j, f, "position", "a point [x, y, z]"), f + ".position")
        r.required(j, f, "radius", "a finite positive number")
        rad = r.pos(j, f, "radius", 0.0)
        vel = r.vec3(j["velocity"], f + ".velocity") if "velocity" in j else (0.0, 0.0, 0.0)
        om = r.vec3(j["angular_velocity"], f + ".angular_velocity") if "angular_velocity" in j else (0.0, 0.0, 0.0)
        fixed = r.boolean(j, f, "fixed", False)
        out.append(Sphere(pos, rad, vel, om, fixed))
    return out


def load_scene(path):
    """Reads and checks a scene file; returns a Scene with every sphere listed."""
    try:
        with open(path, "r", encoding="utf-8") as fh:
            text = fh.read()
    except OSError as e:
        raise SceneError(f"{path}: cannot open the scene file ({e.strerror})") from None
    try:
        j = loads_json_with_comments(text)
    except ValueError as e:
        raise SceneError(f"{path}: not valid JSON: {e}") from None
    return build_scene(j, path)


def build_scene(j, source):
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
    rng = MT19937_64(seed)
    if "generate" in parts:
        sc.spheres.extend(_generated_spheres(r, sc, parts["generate"], rng))
    if "bodies" in parts:
        sc.spheres.extend(_listed_spheres(r, parts["bodies"]))
    if not sc.spheres:
        r.fail("particles", "at least one body (generate.count > 0 or a bodies list)")
    return sc
