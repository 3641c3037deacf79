#!/usr/bin/python3
"""Scene JSON (spheres) -> LIGGGHTS 3.8.0 input deck, STL wall meshes and meta.json.

    /usr/bin/python3 -m liggghts.translate SCENE.json --out DIR [--E 5e6] [--restitution 0.2] ...
    (from scripts/, or scripts/liggghts/translate.py SCENE.json --out DIR)

The spheres come from the engine: `ratchet bodies SCENE.json` (binary: $RATCHET_BIN, else
<$RATCHET_BUILD_DIR or build>/reference_engine/ratchet) writes the bodies exactly as
`ratchet run` starts from them; the scene's other settings are read by scene.py.

DIR receives
    in.liggghts        the deck (run it from DIR: `liggghts -in in.liggghts`)
    particles.data     read_data file: the scene's spheres (the positions, radii and
                       velocities `ratchet bodies` wrote)
    meshes/*.stl       one STL per wall: the floor and each side segment of the cone
                       (two triangles, widened past the corners and below the floor),
                       or one square per plane of a `planes` container
    meta.json          everything the parser needs: units, walls, stages, thermo columns
    post/              (empty) the deck writes stage_NN.dump snapshots there

Which LIGGGHTS command carries which part of the physics is written in docs/liggghts.md.
"""

import argparse
import json
import math
import os
import sys
from dataclasses import dataclass, asdict

if __package__ in (None, ""):
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    __package__ = "liggghts"  # noqa: A001

from common.fsutil import write_atomic  # noqa: E402

from .scene import EngineError, SceneError, load_scene  # noqa: E402
from .units import Units, rayleigh_time  # noqa: E402

DECK = "in.liggghts"
DATA = "particles.data"
META = "meta.json"
LOG = "log.liggghts"
COMPLETE_MARK = "ratchet-deck-complete"   # printed by the last line of the deck


@dataclass
class DemOptions:
    youngs_modulus: float = 5e6      # Pa, particles and walls
    poisson: float = 0.3
    restitution: float = 0.2         # all pairs: quasi-static damping, see docs/liggghts.md
    dt_fraction: float = 0.1         # of the Rayleigh time of the smallest particle
    length_unit: float = 0.01        # m per engine length unit (r_max = 1 -> 1 cm)
    density: float = 2500.0          # kg/m^3
    thermo_interval: float = 0.05    # engine time units between thermo rows
    skin: float = 0.2                # neighbour skin, engine length units
    floor_depth: float = 1.0         # side meshes reach this far below the floor (engine units)
    widen: float = 1.0               # side meshes reach this far past each polygon corner
    top_margin: float = 3.0          # side meshes reach this far above the highest particle
    check_timestep: bool = True


def fmt(x):
    """Shortest text that reads back to the same double."""
    return repr(float(x))


def _sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def _add(*vs):
    return tuple(sum(c) for c in zip(*vs))


def _mul(s, v):
    return tuple(s * x for x in v)


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _unit(v):
    n = math.sqrt(_dot(v, v))
    return _mul(1.0 / n, v)


def stl_text(name, quads_or_tris):
    """ASCII STL. Each facet is a vertex triple wound counter-clockwise seen from the
    side its normal points to (the right-hand rule gives the stated normal)."""
    lines = [f"solid {name}"]
    for tri in quads_or_tris:
        a, b, c = tri
        n = _unit(_cross(_sub(b, a), _sub(c, a)))
        lines.append("  facet normal " + " ".join(f"{x:.17g}" for x in n))
        lines.append("    outer loop")
        for v in tri:
            lines.append("      vertex " + " ".join(f"{x:.17g}" for x in v))
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append(f"endsolid {name}")
    return "\n".join(lines) + "\n"


def quad_triangles(p0, p1, p2, p3):
    """Two triangles of the quad p0 p1 p2 p3 (counter-clockwise)."""
    return [(p0, p1, p2), (p0, p2, p3)]


def cone_side_quad(k, segments, bottom_radius, theta, s_max, z_bottom, z_top, widen):
    """Corners (engine units) of side segment k: the plane through
    p_k = (r_c cos phi_k, r_c sin phi_k, 0) with inward normal
    n_k = (-cos th cos phi_k, -cos th sin phi_k, sin th), from z_bottom (< 0: below the
    floor) to z_top, half-width at height z (s_max r_c + z tan th) tan(pi/N) + widen so
    that it still covers the polygon corners when the container has expanded to s_max
    (faces translate along their normals and do not stretch). Wound so that the
    right-hand normal is the inward normal n_k."""
    phi = 2.0 * math.pi * k / segments
    p = (bottom_radius * math.cos(phi), bottom_radius * math.sin(phi), 0.0)
    up = (math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta))  # in-plane, upward
    tang = (-math.sin(phi), math.cos(phi), 0.0)  # in-plane, horizontal (azimuthal)
    t_half = math.tan(math.pi / segments)

    def corner(z, side):
        w = (s_max * bottom_radius + max(z, 0.0) * math.tan(theta)) * t_half + widen
        return _add(p, _mul(z / math.cos(theta), up), _mul(side * w, tang))

    b_r, b_l = corner(z_bottom, +1.0), corner(z_bottom, -1.0)
    t_r, t_l = corner(z_top, +1.0), corner(z_top, -1.0)
    # tang x up = (cos th cos phi, cos th sin phi, -sin th) is the outward normal, so the
    # counter-clockwise order seen from inside runs against `tang` along the bottom edge.
    quad = (b_r, b_l, t_l, t_r)
    n = _unit(_cross(_sub(quad[1], quad[0]), _sub(quad[2], quad[0])))
    n_inward = (-math.cos(theta) * math.cos(phi), -math.cos(theta) * math.sin(phi), math.sin(theta))
    assert _dot(n, n_inward) > 0.999999
    return quad


def plane_quad(normal, point, center, half):
    """Square of half-size `half` in the plane (normal, point), centred at the projection
    of `center`, wound so that the right-hand normal is `normal`."""
    n = _unit(normal)
    foot = _sub(center, _mul(_dot(_sub(center, point), n), n))
    helper = (1.0, 0.0, 0.0) if abs(n[0]) < 0.9 else (0.0, 1.0, 0.0)
    e1 = _unit(_cross(n, helper))
    e2 = _cross(n, e1)  # e1 x e2 = n
    return (_add(foot, _mul(-half, e1), _mul(-half, e2)), _add(foot, _mul(half, e1), _mul(-half, e2)),
            _add(foot, _mul(half, e1), _mul(half, e2)), _add(foot, _mul(-half, e1), _mul(half, e2)))


def _scale_range(scene):
    """(s_min, s_max) of the container scale over the protocol."""
    if not scene.container_expansion_on():
        return 1.0, 1.0
    th = scene.thermal
    s1 = 1.0 + th.alpha_c * (th.T1 - th.T0)
    return min(1.0, s1), max(1.0, s1)


def build_walls(scene, opts):
    """Wall meshes in engine units: list of dicts {id, role, normal, point, quad, moving}."""
    walls = []
    s_min, s_max = _scale_range(scene)
    tops = [sp.position[2] + sp.radius for sp in scene.spheres]
    if scene.container_type == "cone":
        th = scene.theta
        z_top = max(max(tops) + opts.top_margin, 1.0)
        # Floor: a square covering the polygon at its largest (corners at a / cos(pi/N)).
        a_max = s_max * scene.bottom_radius + z_top * math.tan(th)
        half = a_max / math.cos(math.pi / scene.segments) + opts.widen + 1.0
        for i, w in enumerate(scene.walls):
            if w.role == "bottom":
                quad = ((-half, -half, 0.0), (half, -half, 0.0), (half, half, 0.0), (-half, half, 0.0))
                walls.append(dict(id="w0", role="bottom", normal=w.normal, point=w.point, quad=quad,
                                  moving=False))
            else:
                k = i - 1
                quad = cone_side_quad(k, scene.segments, scene.bottom_radius, th, s_max, -opts.floor_depth,
                                      z_top, opts.widen)
                walls.append(dict(id=f"w{i}", role="side", normal=w.normal, point=w.point, quad=quad,
                                  moving=scene.container_expansion_on()))
    elif scene.container_type == "planes":
        pts = [sp.position for sp in scene.spheres]
        lo = [min(p[i] - sp.radius for p, sp in zip(pts, scene.spheres)) for i in range(3)]
        hi = [max(p[i] + sp.radius for p, sp in zip(pts, scene.spheres)) for i in range(3)]
        center = tuple(0.5 * (a + b) for a, b in zip(lo, hi))
        half = 0.5 * math.sqrt(sum((b - a) ** 2 for a, b in zip(lo, hi))) + 5.0
        for i, w in enumerate(scene.walls):
            reach = abs(_dot(w.normal, w.point)) * (s_max - 1.0) if w.expands else 0.0
            quad = plane_quad(w.normal, w.point, center, half + reach)
            walls.append(dict(id=f"w{i}", role="plane", normal=w.normal, point=w.point, quad=quad,
                              moving=w.expands and scene.container_expansion_on()))
    return walls


def simulation_box(scene, walls, opts):
    """Box (engine units) holding every particle and every mesh in all its positions."""
    s_min, s_max = _scale_range(scene)
    pts = []
    for sp in scene.spheres:
        pts.append(_add(sp.position, (sp.radius,) * 3))
        pts.append(_sub(sp.position, (sp.radius,) * 3))
    for w in walls:
        for v in w["quad"]:
            pts.append(v)
            if w["moving"]:
                d = _dot(w["normal"], w["point"])
                for s in (s_min, s_max):
                    pts.append(_add(v, _mul((s - 1.0) * d, w["normal"])))
    lo = [min(p[i] for p in pts) - 1.0 for i in range(3)]
    hi = [max(p[i] for p in pts) + 1.0 for i in range(3)]
    return lo, hi


def dem_stages(scene, dt_si, units):
    """Stages with cumulative DEM step bounds; a stage of zero steps is dropped."""
    out = []
    for kind, a, b, Ta, Tb in scene.stages():
        s0 = int(round(a * units.time / dt_si))
        s1 = int(round(b * units.time / dt_si))
        if s1 > s0:
            out.append(dict(kind=kind, t_begin=a, t_end=b, T_begin=Ta, T_end=Tb, step_begin=s0, step_end=s1))
    # Contiguous by construction (same rounding at shared bounds).
    for x, y in zip(out, out[1:]):
        y["step_begin"] = x["step_end"]
    return out


def translate(scene, outdir, opts=None):
    """Writes the deck, data, meshes and meta.json into `outdir`; returns the meta dict."""
    opts = opts or DemOptions()
    if opts.youngs_modulus <= 0 or not math.isfinite(opts.youngs_modulus):
        raise SceneError(f"--E: expected a positive Young's modulus in Pa, got {opts.youngs_modulus}")
    if not 0.0 < opts.restitution <= 1.0:
        raise SceneError(f"--restitution: expected a value in (0, 1], got {opts.restitution}")
    units = Units(length=opts.length_unit, density_si=opts.density, density_scene=scene.density)
    L = units.length
    os.makedirs(os.path.join(outdir, "meshes"), exist_ok=True)
    os.makedirs(os.path.join(outdir, "post"), exist_ok=True)

    r_min = min(sp.radius for sp in scene.spheres)
    r_max = max(sp.radius for sp in scene.spheres)
    t_r = rayleigh_time(r_min * L, opts.density, opts.youngs_modulus, opts.poisson)
    dt = opts.dt_fraction * t_r
    stages = dem_stages(scene, dt, units)
    thermo_every = max(1, int(round(opts.thermo_interval * units.time / dt)))

    walls = build_walls(scene, opts)
    lo, hi = simulation_box(scene, walls, opts)

    # Meshes.
    for w in walls:
        text = stl_text(w["id"], quad_triangles(*[_mul(L, v) for v in w["quad"]]))
        w["file"] = f"meshes/{w['id']}.stl"
        write_atomic(os.path.join(outdir, w["file"]), text)

    # Particles (read_data, atom_style granular: id type diameter density x y z).
    rho = opts.density
    lines = [f"LIGGGHTS data file: {len(scene.spheres)} spheres of scene {scene.name} ({scene.source})", "",
             f"{len(scene.spheres)} atoms", "2 atom types", "",
             f"{lo[0] * L:.17g} {hi[0] * L:.17g} xlo xhi", f"{lo[1] * L:.17g} {hi[1] * L:.17g} ylo yhi",
             f"{lo[2] * L:.17g} {hi[2] * L:.17g} zlo zhi", "", "Atoms", ""]
    for i, sp in enumerate(scene.spheres, start=1):
        x, y, z = (c * L for c in sp.position)
        lines.append(f"{i} 1 {2.0 * sp.radius * L:.17g} {rho:.17g} {x:.17g} {y:.17g} {z:.17g}")
    moving_init = any(any(v != 0.0 for v in sp.velocity + sp.angular_velocity) for sp in scene.spheres)
    if moving_init:
        lines += ["", "Velocities", ""]
        for i, sp in enumerate(scene.spheres, start=1):
            v = [c * units.velocity for c in sp.velocity] + [c / units.time for c in sp.angular_velocity]
            lines.append(f"{i} " + " ".join(f"{c:.17g}" for c in v))
    write_atomic(os.path.join(outdir, DATA), "\n".join(lines) + "\n")

    eff = scene.effects
    mu = scene.friction if eff["friction"] else 0.0
    mu_w = scene.wall_friction if eff["friction"] else 0.0
    e = opts.restitution
    E = opts.youngs_modulus
    g_vec = scene.gravity if eff["gravity"] else (0.0, 0.0, 0.0)
    g_mag = math.sqrt(_dot(g_vec, g_vec))
    th = scene.thermal
    T0 = th.T0 if th else 0.0
    alpha_p = th.alpha_p if (th and scene.particle_expansion_on()) else 0.0
    alpha_c = th.alpha_c if (th and scene.container_expansion_on()) else 0.0
    fixed_ids = [i for i, sp in enumerate(scene.spheres, start=1) if sp.fixed]

    d = []
    w_ = d.append
    w_(f"# LIGGGHTS 3.8.0 deck written by scripts/liggghts/translate.py from {scene.source}")
    w_(f"# scene '{scene.name}': {len(scene.spheres)} spheres, container {scene.container_type}")
    w_(f"# units: SI; engine length unit L = {L} m, time unit sqrt(L/g0) = {units.time:.6g} s,")
    w_(f"#        mass unit {units.mass:.6g} kg, force unit {units.force:.6g} N (docs/liggghts.md)")
    w_(f"# Hertz, E = {E:g} Pa, nu = {opts.poisson}, restitution {e}, friction {mu} / wall {mu_w}")
    w_(f"# time step {dt:.6g} s = {opts.dt_fraction} x Rayleigh time {t_r:.6g} s of r_min = {r_min * L:.6g} m")
    w_("")
    w_("atom_style      granular")
    w_("atom_modify     map array")
    w_("boundary        f f f")
    w_("newton          off")
    w_("communicate     single vel yes")
    w_("units           si")
    if E < 5e6:
        w_("soft_particles  yes")
    if E > 1e9:
        w_("hard_particles  yes")
    w_(f"read_data       {DATA}")
    w_(f"neighbor        {opts.skin * L:.6g} bin")
    w_("neigh_modify    delay 0")
    w_("")
    w_("# material: type 1 = particles, type 2 = walls")
    w_(f"fix m1 all property/global youngsModulus peratomtype {E:.10g} {E:.10g}")
    w_(f"fix m2 all property/global poissonsRatio peratomtype {opts.poisson} {opts.poisson}")
    w_(f"fix m3 all property/global coefficientRestitution peratomtypepair 2 {e} {e} {e} {e}")
    w_(f"fix m4 all property/global coefficientFriction peratomtypepair 2 {mu!r} {mu_w!r} {mu_w!r} {mu_w!r}")
    w_("pair_style      gran model hertz tangential history")
    w_("pair_coeff      * *")
    w_(f"timestep        {dt:.17g}")
    w_("")
    if fixed_ids:
        w_("group           fixed id " + " ".join(str(i) for i in fixed_ids))
        w_("group           mobile subtract all fixed")
    else:
        w_("group           mobile type 1")
    w_("")
    w_("# thermal state: T(step) is redefined for every stage below")
    w_(f"variable        T equal {T0!r}")
    w_(f"variable        sp equal 1.0+{alpha_p!r}*(v_T-{T0!r})")
    w_(f"variable        sc equal 1.0+{alpha_c!r}*(v_T-{T0!r})")
    if alpha_p != 0.0:
        w_("# particle expansion: d = d0 s_p for every particle from its own initial radius")
        w_("fix             r0 mobile store/state 0 radius")
        w_("variable        dnew atom 2.0*f_r0*v_sp")
        w_("fix             grow mobile adapt 1 atom diameter v_dnew")
    if g_mag > 0.0:
        gdir = _unit(g_vec)
        if alpha_p != 0.0:
            w_("# fix adapt keeps the density, so the mass grows with s_p^3: scale g by 1/s_p^3")
            w_(f"variable        gmag equal {g_mag * units.g0!r}/(v_sp*v_sp*v_sp)")
            w_("fix             grav mobile gravity v_gmag vector " + " ".join(fmt(c) for c in gdir))
        else:
            w_(f"fix             grav mobile gravity {g_mag * units.g0!r} vector " + " ".join(fmt(c) for c in gdir))
    if eff["rotation"]:
        w_("fix             integ mobile nve/sphere")
    else:
        w_("# effects.rotation false: translation only, angular velocities stay zero")
        w_("fix             integ mobile nve")
    w_("")
    if walls:
        w_("# walls: one mesh per wall (type 2); reference point = the wall's point p")
        for wl in walls:
            rp = " ".join(f"{c * L:.17g}" for c in wl["point"])
            w_(f"fix             {wl['id']} all mesh/surface/stress file {wl['file']} type 2 reference_point {rp}")
        w_(f"fix             walls mobile wall/gran model hertz tangential history mesh n_meshes {len(walls)} "
           f"meshes " + " ".join(wl["id"] for wl in walls))
        w_("")
    w_("# observers")
    w_("compute         rad mobile property/atom radius")
    w_("variable        top atom z+c_rad")
    w_("compute         top mobile reduce max v_top")
    w_("compute         ket mobile ke")
    w_("compute         kerot mobile erotate/sphere")
    if walls:
        # per particle-wall contact: mesh index (order of the wall/gran list), triangle,
        # particle id, force on the particle (3); must exist before the first run
        w_("compute         wl mobile wall/gran/local id force")
    columns = ["step", "v_T", "v_sp", "v_sc", "c_ket", "c_kerot", "c_top"]
    for wl in walls:
        columns += [f"f_{wl['id']}[1]", f"f_{wl['id']}[2]", f"f_{wl['id']}[3]"]
    ref_wall = next((wl for wl in walls if wl["moving"]), None)
    if ref_wall is not None:
        columns += [f"f_{ref_wall['id']}[7]", f"f_{ref_wall['id']}[8]", f"f_{ref_wall['id']}[9]"]
    w_("thermo_style    custom " + " ".join(columns))
    w_(f"thermo          {thermo_every}")
    w_("thermo_modify   norm no lost error format float %.12g")
    if opts.check_timestep:
        w_(f"fix             tscheck all check/timestep/gran {max(1000, thermo_every * 100)} 0.2 0.2")
    w_("")
    dumps = []
    wall_dumps = []
    for i, st in enumerate(stages):
        n = st["step_end"] - st["step_begin"]
        w_(f"# stage {i}: {st['kind']} t = {st['t_begin']:.6g} .. {st['t_end']:.6g} (engine units), "
           f"steps {st['step_begin']} .. {st['step_end']}")
        if st["T_end"] != st["T_begin"]:
            w_(f"variable        T equal {st['T_begin']!r}+({st['T_end'] - st['T_begin']!r})*"
               f"(step-{st['step_begin']})/{n}")
        else:
            w_(f"variable        T equal {st['T_begin']!r}")
        movers = []
        if alpha_c != 0.0 and st["T_end"] != st["T_begin"]:
            # Container scaling about the origin moves each planar face along its normal:
            # offset (s_c - 1) (n . p); constant velocity over the ramp.
            ds = alpha_c * (st["T_end"] - st["T_begin"])
            for wl in walls:
                if not wl["moving"]:
                    continue
                dist = ds * _dot(wl["normal"], wl["point"]) * L
                v = _mul(dist / (n * dt), wl["normal"])
                mid = f"mv_{wl['id']}"
                movers.append(mid)
                w_(f"fix             {mid} all move/mesh mesh {wl['id']} linear " + " ".join(f"{c:.17g}" for c in v))
        wall_dump = None
        if walls and st["kind"] in ("settle", "cool") and scene.container_type == "cone":
            # Per-contact wall forces at the stage end (for the wall stress profile):
            # a local dump over the last step only.
            wall_dump = f"post/walls_stage_{i:02d}.local"
            if n > 1:
                w_(f"run             {n - 1}")
            w_(f"dump            wdump mobile local 1 {wall_dump} " + " ".join(f"c_wl[{k}]" for k in range(1, 7)))
            w_("run             1")
            w_("undump          wdump")
            wall_dumps.append(dict(stage=i, file=wall_dump, step=st["step_end"], t=st["t_end"], kind=st["kind"]))
        else:
            w_(f"run             {n}")
        for mid in movers:
            w_(f"unfix           {mid}")
        dump = f"post/stage_{i:02d}.dump"
        w_(f"write_dump      all custom {dump} id type x y z vx vy vz radius modify sort id "
           "format \"%d %d %.12g %.12g %.12g %.12g %.12g %.12g %.12g\"")
        dumps.append(dict(stage=i, file=dump, step=st["step_end"], t=st["t_end"]))
        w_("")
    w_(f"print           \"{COMPLETE_MARK}\"")
    write_atomic(os.path.join(outdir, DECK), "\n".join(d) + "\n")

    meta = dict(
        format="ratchet-liggghts-meta/1",
        scene_file=os.path.abspath(scene.source), scene_name=scene.name,
        options=asdict(opts), units=units.to_dict(),
        dt_si=dt, rayleigh_time_si=t_r, r_min=r_min, r_max=r_max, n_particles=len(scene.spheres),
        n_fixed=len(fixed_ids), fixed_ids=fixed_ids,
        sphere_volume=sum(4.0 / 3.0 * math.pi * sp.radius ** 3 for sp in scene.spheres if not sp.fixed),
        thermo_every=thermo_every, columns=columns, reference_wall=ref_wall["id"] if ref_wall else None,
        container=dict(type=scene.container_type, bottom_radius=scene.bottom_radius,
                       opening_angle_deg=scene.opening_angle_deg, segments=scene.segments),
        thermal=(asdict(th) if th else None), alpha_p_used=alpha_p, alpha_c_used=alpha_c,
        walls=[dict(id=wl["id"], role=wl["role"], normal=list(wl["normal"]), point=list(wl["point"]),
                    file=wl["file"], moving=wl["moving"]) for wl in walls],
        stages=stages, dumps=dumps, wall_dumps=wall_dumps, deck=DECK, log=LOG, box_lo=lo, box_hi=hi,
        total_steps=stages[-1]["step_end"] if stages else 0,
    )
    write_atomic(os.path.join(outdir, META), json.dumps(meta, indent=2) + "\n")
    return meta


def options_from_args(args):
    return DemOptions(youngs_modulus=args.E, poisson=args.poisson, restitution=args.restitution,
                      dt_fraction=args.dt_fraction, length_unit=args.length_unit, density=args.density,
                      thermo_interval=args.thermo_interval)


def add_dem_arguments(ap, multiple_E=False):
    if multiple_E:
        ap.add_argument("--E", type=float, nargs="+", default=[5e6], metavar="PA",
                        help="Young's modulus of particles and walls in Pa, one DEM run each (default 5e6)")
    else:
        ap.add_argument("--E", type=float, default=5e6, metavar="PA",
                        help="Young's modulus of particles and walls in Pa (default 5e6)")
    ap.add_argument("--poisson", type=float, default=0.3, help="Poisson's ratio (default 0.3)")
    ap.add_argument("--restitution", type=float, default=0.2,
                    help="coefficient of restitution of every contact (default 0.2: quasi-static damping)")
    ap.add_argument("--dt-fraction", type=float, default=0.1,
                    help="time step as a fraction of the Rayleigh time of the smallest particle (default 0.1)")
    ap.add_argument("--length-unit", type=float, default=0.01, help="metres per engine length unit (default 0.01)")
    ap.add_argument("--density", type=float, default=2500.0, help="DEM particle density, kg/m^3 (default 2500)")
    ap.add_argument("--thermo-interval", type=float, default=0.05,
                    help="engine time units between output rows (default 0.05)")


def main(argv=None):
    ap = argparse.ArgumentParser(description="Translate a ratchet sphere scene into a LIGGGHTS deck.")
    ap.add_argument("scene", help="scene JSON file")
    ap.add_argument("--out", required=True, help="output folder (created)")
    add_dem_arguments(ap)
    args = ap.parse_args(argv)
    try:
        scene = load_scene(args.scene)
        meta = translate(scene, args.out, options_from_args(args))
    except SceneError as e:
        print(f"translate: error: {e}", file=sys.stderr)
        return 2
    except EngineError as e:
        print(f"translate: error: {e}", file=sys.stderr)
        return 1
    print(f"translate: {meta['n_particles']} spheres, {len(meta['walls'])} wall meshes, "
          f"{meta['total_steps']} steps of {meta['dt_si']:.4g} s -> {os.path.join(args.out, DECK)}",
          file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
