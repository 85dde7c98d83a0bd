"""The finite-segment springs' compliance integral ∫ dx / (w(x) t(x)^3) under a thickness law.

With w and t both linear on a sub-interval, 1 / (w t^3) has poles just outside it when either
tapers steeply (a near-wedge: t falls a hundredfold over one interval). Gauss-Legendre on the
whole sub-interval would converge slowly there, so each sub-interval is cut where w or t has
changed by a factor ``_RATIO``: on each piece the nearest pole lies at least 1 / (_RATIO - 1)
piece lengths away, and 8 Gauss points give the integral to rounding (Bernstein ellipse
parameter ~10 at _RATIO = 1.5: error ~10^-16).

A round member's 1 / E I_y = 64 / (E pi (D - d) (D + d) (D^2 + d^2)) is cut the same way where
D - d or D + d has changed by ``_RATIO``: on a piece where both p = D + d and q = D - d change by
at most that factor, the complex roots of D^2 + d^2 = (p^2 + q^2) / 2 lie at least
1 / (_RATIO - 1) piece lengths away too (|p'| <= (_RATIO - 1) p, |q'| <= (_RATIO - 1) q).
A section table's stiffness S is itself linear between stations: it is cut where S has changed
by ``_RATIO``, its one pole as far away.
"""

from __future__ import annotations

import numpy as np

from ..member.geometry import Beam
from ..member.section_law import section_properties

__all__ = ["inverse_moment_integral", "inverse_section_integral"]

_RATIO = 1.5
_GX, _GW = np.polynomial.legendre.leggauss(8)
_GX = 0.5 * (_GX + 1.0)  # on [0, 1]
_GW = 0.5 * _GW


def _geometric_cuts(f0: np.ndarray, f1: np.ndarray, k: np.ndarray) -> np.ndarray:
    """Fractions s in [0, 1] where the linear f0 + (f1 - f0) s is f0 (f1 / f0)^k."""
    d = f1 - f0
    flat = np.abs(d) <= 1e-12 * f0
    s = (f0[..., None] * ((f1 / f0)[..., None] ** k - 1.0)) / np.where(flat, 1.0, d)[..., None]
    return np.clip(np.where(flat[..., None], k, s), 0.0, 1.0)


def inverse_moment_integral(beam: Beam, cuts: np.ndarray):
    """Return u, v (m) and ∫_u^v dx / (w t^3) (m^-3) of each sub-interval between ``cuts``.

    ``cuts`` (B, c), m, sorted, include the stations, so w and t are linear on each
    sub-interval; at a width step w's one-sided limits are used (t is continuous).
    """
    u, v = cuts[:, :-1], cuts[:, 1:]
    wu = np.asarray(beam.half_width_at(u, "right"), dtype=float)
    wv = np.asarray(beam.half_width_at(v, "left"), dtype=float)
    tu = np.interp(u, beam.x_m, beam.thickness_law_m)
    tv = np.interp(v, beam.x_m, beam.thickness_law_m)
    spread = max(float(np.max(np.maximum(wu / wv, wv / wu))),
                 float(np.max(np.maximum(tu / tv, tv / tu))))
    m = max(1, int(np.ceil(np.log(spread) / np.log(_RATIO))))
    k = np.arange(m + 1) / m
    s = np.sort(np.concatenate([_geometric_cuts(wu, wv, k), _geometric_cuts(tu, tv, k)],
                               axis=-1), axis=-1)
    a, b = s[..., :-1], s[..., 1:]
    sg = a[..., None] + (b - a)[..., None] * _GX  # (B, subs, pieces, 8)
    w = wu[..., None, None] + (wv - wu)[..., None, None] * sg
    t = tu[..., None, None] + (tv - tu)[..., None, None] * sg
    inner = np.sum((b - a)[..., None] * _GW / (w * t**3), axis=(-1, -2))
    return u, v, (v - u) * inner


def inverse_section_integral(beam: Beam, cuts: np.ndarray, stiffness: str = "EI_y_Nm2"):
    """Return u, v (m) and ∫_u^v dx / S(x) (1/(N m)) of each sub-interval between ``cuts``.

    For a member with a section law (``beam.section``); ``cuts`` (B, c), m, sorted, include
    the stations, so the diameters are linear on each sub-interval. ``stiffness`` names the
    :class:`~prbdm_pin.member.section_law.SectionProperties` field S: ``"EI_y_Nm2"`` (the
    planar springs), ``"EI_z_Nm2"`` or ``"GJ_Nm2"`` (N m^2), all proportional to D^4 - d^4.
    """
    u, v = cuts[:, :-1], cuts[:, 1:]
    sec = beam.section
    if sec.kind == "table":  # S itself is linear: its pole is cut away from
        table = getattr(sec, stiffness)
        factors = (tuple(np.interp(z, beam.x_m, table) for z in (u, v)),)
    else:
        Du, Dv = (np.interp(z, beam.x_m, sec.outer_diameter_m) for z in (u, v))
        du, dv = (np.interp(z, beam.x_m, sec.inner_diameter_m) for z in (u, v))
        factors = ((Du + du, Dv + dv), (Du - du, Dv - dv))
    spread = max(float(np.max(np.maximum(a / b, b / a))) for a, b in factors)
    m = max(1, int(np.ceil(np.log(spread) / np.log(_RATIO))))
    k = np.arange(m + 1) / m
    s = np.sort(np.concatenate([_geometric_cuts(a, b, k) for a, b in factors], axis=-1),
                axis=-1)
    a, b = s[..., :-1], s[..., 1:]
    sg = a[..., None] + (b - a)[..., None] * _GX  # (B, subs, pieces, 8)
    x = u[..., None, None] + (v - u)[..., None, None] * sg
    S = getattr(section_properties(beam, x), stiffness)
    inner = np.sum((b - a)[..., None] * _GW / S, axis=(-1, -2))
    return u, v, (v - u) * inner
