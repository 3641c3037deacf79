"""Mapping between the engine's dimensionless units and the SI units of the DEM run.

Engine units (docs/scene-format.md): length r_max = 1, acceleration g = 1, time
sqrt(r_max / g), density `materials.density` (default 1), so
    mass unit     M = rho_SI L^3 / rho_scene      (a sphere of radius r has mass
                                                   rho_scene (4/3) pi r^3 M in both)
    force unit    F = M g0
    pressure unit F / L^2 = rho_SI g0 L / rho_scene
    energy unit   F L
with L = length_unit (default 0.01 m: r_max = 1 cm), rho_SI the DEM density
(default 2500 kg/m^3) and g0 = 9.81 m/s^2.
"""

import math
from dataclasses import dataclass, asdict

G0 = 9.81


@dataclass
class Units:
    length: float = 0.01          # m per engine length unit (r_max)
    density_si: float = 2500.0    # kg/m^3 of the DEM particles
    density_scene: float = 1.0    # materials.density of the scene
    g0: float = G0                # m/s^2 per engine acceleration unit

    @property
    def time(self):
        return math.sqrt(self.length / self.g0)

    @property
    def mass(self):
        return self.density_si * self.length ** 3 / self.density_scene

    @property
    def force(self):
        return self.mass * self.g0

    @property
    def pressure(self):
        return self.force / self.length ** 2

    @property
    def energy(self):
        return self.force * self.length

    @property
    def velocity(self):
        return self.length / self.time

    def to_dict(self):
        d = asdict(self)
        d.update(time=self.time, mass=self.mass, force=self.force, pressure=self.pressure, energy=self.energy)
        return d

    @classmethod
    def from_dict(cls, d):
        return cls(length=d["length"], density_si=d["density_si"], density_scene=d["density_scene"], g0=d["g0"])


def rayleigh_time(radius_si, density_si, youngs_modulus, poisson):
    """t_R = pi r sqrt(rho / G) / (0.1631 nu + 0.8766), G = E / (2 (1 + nu))
    (LIGGGHTS fix check/timestep/gran)."""
    shear = youngs_modulus / (2.0 * (1.0 + poisson))
    return math.pi * radius_si * math.sqrt(density_si / shear) / (0.1631 * poisson + 0.8766)


def frustum_side_area(height, bottom_radius, theta, segments, s_c=1.0):
    """Lateral area of the N-sided frustum from z = 0 to `height` (the engine's
    World::wetted_side_area): N (a0 + a1) tan(pi/N) H / cos(theta), a0 = s_c r_c,
    a1 = a0 + H tan(theta). Works element-wise on numpy arrays; 0 where height <= 0."""
    import numpy as np
    h = np.asarray(height, dtype=float)
    a0 = np.asarray(s_c, dtype=float) * bottom_radius
    a1 = a0 + h * math.tan(theta)
    area = segments * (a0 + a1) * math.tan(math.pi / segments) * h / math.cos(theta)
    return np.where(h > 0.0, area, 0.0)


def frustum_volume(height, bottom_radius, theta, segments, s_c=1.0):
    """Volume of the N-sided frustum from z = 0 to `height`: the cross-section at z is
    the regular N-gon of apothem a(z) = s_c r_c + z tan(theta), area N a^2 tan(pi/N)."""
    a0 = s_c * bottom_radius
    t = math.tan(theta)
    # integral of a(z)^2 dz from 0 to H
    integral = a0 * a0 * height + a0 * t * height ** 2 + t * t * height ** 3 / 3.0
    return segments * math.tan(math.pi / segments) * integral
