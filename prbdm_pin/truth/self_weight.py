"""A member's self weight: the gravity vector it is given and the weight outboard of a section.

The member lies along +x from the clamped root (x = 0) to the free tip (x = L) and bends in the
x-z plane. Under a uniform gravity g (m/s^2, world = member axes at the straight pose) the part
outboard of the station x weighs g m_out(x), ``m_out(x) = int_x^L rho A(s) ds``: its x component
is the section's axial force (tension for g_x > 0, the member hanging from its root; compression
for g_x < 0, the member standing on it), its z component the shear the sag carries.

Light on purpose (numpy only): the elastica and the command line use it without the
finite-element code.
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError
from ..member.geometry import Beam

__all__ = ["MAX_GRAVITY_M_S2", "check_gravity", "outboard_mass_kg"]

# the largest gravity the truth takes, m/s^2 (about 100 g): a member under more is a crash
# load, not a structure at rest; it is also far past where an elastica under its own weight
# folds back on itself for any strip the package ships (a typed unit slip, e.g. mm/s^2, lands
# here)
MAX_GRAVITY_M_S2 = 1000.0


def check_gravity(value, name: str = "gravity_m_s2", planar: bool = True) -> np.ndarray:
    """Return a gravity vector (3,) in m/s^2; BeamInputError naming ``name`` otherwise.

    Parameters
    ----------
    value : array_like, shape (3,)
        Gravity, m/s^2, in the member's axes (x along the member from the root).
    name : str
        The argument or option the errors name (``--gravity`` from the command line).
    planar : bool
        Refuse a y component (the 1D truth and the planar chain bend in x-z only).

    Raises
    ------
    BeamInputError
        Not 3 finite numbers, a magnitude above ``MAX_GRAVITY_M_S2``, or (``planar``) g_y != 0.
    """
    try:
        g = np.array(value, dtype=float)
    except (TypeError, ValueError):
        g = np.array([np.nan])
    if g.shape != (3,) or not np.all(np.isfinite(g)):
        raise BeamInputError(f"{name} = {value!r}: must be 3 finite numbers (m/s^2)")
    size = float(np.linalg.norm(g))
    if size > MAX_GRAVITY_M_S2:
        raise BeamInputError(f"{name} = {g.tolist()}: |g| = {size:.4g} m/s^2 is above "
                             f"{MAX_GRAVITY_M_S2:g} m/s^2 (about 100 g; a unit slip?)")
    if planar and g[1] != 0.0:
        raise BeamInputError(f"{name} = {g.tolist()}: g_y must be 0 (the 1D beam truth and the "
                             "planar chain bend in the x-z plane only)")
    return g


def outboard_mass_kg(beam: Beam, x_m) -> np.ndarray:
    """Return m_out(x) = int_x^L rho A(s) ds, kg: the mass outboard of each station ``x_m`` (m).

    Exact for the piecewise-linear planform (rho A = rho t 2 w(s) is linear between vertices;
    a width step's zero-length interval adds nothing).
    """
    x = np.clip(np.asarray(x_m, dtype=float), 0.0, beam.length_m)
    xv, wv = beam.x_m, beam.half_width_m
    rho_t = beam.material.rho_kg_m3 * beam.uniform_thickness_m("the self-weight truth")
    # mass of each vertex interval (trapezoid of 2 w: exact for linear w), summed from the tip
    seg = rho_t * (wv[:-1] + wv[1:]) * np.diff(xv)
    tail = np.concatenate([np.cumsum(seg[::-1])[::-1], [0.0]])  # mass outboard of vertex i
    # the interval of positive length holding x (after a step's repeated vertex)
    i = np.clip(np.searchsorted(xv, x, side="right") - 1, 0, xv.size - 2)
    dx = xv[i + 1] - xv[i]
    frac = np.divide(x - xv[i], dx, out=np.zeros_like(x), where=dx > 0.0)
    w = wv[i] + (wv[i + 1] - wv[i]) * frac
    return rho_t * (w + wv[i + 1]) * (xv[i + 1] - x) + tail[i + 1]
