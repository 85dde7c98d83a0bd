"""Published and prototype reference values the tests compare against, each written once.

Imported as ``from reference import ...``: pytest puts this folder on ``sys.path`` for the test
modules in it (rootdir-relative ``tests/`` without ``__init__.py``).
"""

from __future__ import annotations

import numpy as np

__all__ = ["BETA_L", "ELASTICA", "REF_OMEGA", "SQUARE_PLATE", "cantilever_modes", "strip_target"]

# clamped-free Euler-Bernoulli roots beta_k L of cos(beta L) cosh(beta L) = -1
BETA_L = np.array([1.8751040687120, 4.6940911329742, 7.8547574382376, 10.995540734875,
                   14.137168391046, 17.278759532088])

# inextensible elastica of a uniform cantilever under a tip load perpendicular to its axis:
# P L^2 / EI -> (tip retreat (L - x)/L, tip deflection y/L), Mattiasson (1981) Table 1
ELASTICA = {
    1.0: (0.056433, 0.301721),
    2.0: (0.160642, 0.493457),
    5.0: (0.387628, 0.713792),
    10.0: (0.554996, 0.810609),
}

# prototype truth for examples/beams/reference-random.json, first five bending modes (rad/s)
REF_OMEGA = np.array([39.65, 333.8, 1018.0, 1974.0, 2800.0])

# converged Kirchhoff cantilever square plate, nu = 0.3: omega a^2 sqrt(rho h / D) of the first
# five modes (Leissa's Ritz values sit 0.2-0.7 % above)
SQUARE_PLATE = np.array([3.4710, 8.5063, 21.284, 27.199, 30.955])

# shared by every test module: read-only, so no test can change another's reference
for _table in (BETA_L, REF_OMEGA, SQUARE_PLATE):
    _table.setflags(write=False)


def cantilever_modes(EI_Nm2: float, mass_per_length_kg_m: float, length_m: float, n: int):
    """Closed-form clamped-free Euler-Bernoulli modes, mass-normalised (int m phi^2 dx = 1):
    omega (rad/s, (n,)), the tip deflection per modal coordinate (positive, (n,)) and
    ``psi(x)`` -> (n,) the section rotation -d phi / dx (the sense of a joint angle: a positive
    psi turns the beam towards -z) at station x (m)."""
    L, bl = length_m, BETA_L[:n]
    beta = bl / L
    omega = bl**2 * np.sqrt(EI_Nm2 / (mass_per_length_kg_m * L**4))
    sigma = (np.cosh(bl) + np.cos(bl)) / (np.sinh(bl) + np.sin(bl))
    a = 1.0 / np.sqrt(mass_per_length_kg_m * L)  # the bracket's square integrates to L

    def shape(x):
        b = beta * x
        return a * (np.cosh(b) - np.cos(b) - sigma * (np.sinh(b) - np.sin(b)))

    sign = np.sign(shape(L))

    def psi(x):
        b = beta * x
        return -sign * a * beta * (np.sinh(b) + np.sin(b) - sigma * (np.cosh(b) - np.cos(b)))

    return omega, sign * shape(L), psi


def strip_target(beam):
    """Euler-Bernoulli frequencies and the elastica tip at P L^2 / EI = 1 of the uniform strip
    of ``beam``'s root width, as a ``FitTarget`` (for a tapered or stepped beam a target the
    model cannot match exactly)."""
    import math

    from prbdm_pin.fitting.target import FitTarget

    b = 2 * beam.half_width_m[0]
    EI = beam.material.E_Pa * b * beam.thickness_m**3 / 12
    omega = BETA_L**2 * math.sqrt(EI / (beam.material.rho_kg_m3 * b * beam.thickness_m))
    L = beam.length_m
    retreat, defl = ELASTICA[1.0]
    return FitTarget(omega, beam.tip_force_N, [L * (1 - retreat), 0.0, -defl * L],
                     [-retreat * L, 0.0, -defl * L], source="Euler-Bernoulli + elastica")
