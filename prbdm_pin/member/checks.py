"""Checks of beam input fields: numbers, arrays, vertex stations, representable magnitudes.

Every check raises :class:`~prbdm_pin.errors.BeamInputError` naming the field, its value and
the unit, so a defect in a beam file or a ``Beam(...)`` call reads the same wherever it is found.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..options.checks import shown

if TYPE_CHECKING:
    from .material import Material

__all__ = ["finite_positive", "float_array", "check_representable", "check_stations",
           "thickness_law"]


def finite_positive(name: str, value: Any) -> float:
    """Return ``value`` as a finite float > 0; a BeamInputError names the field ``name``.

    A value that is not a real number raises :class:`~prbdm_pin.errors.InputTypeError` (a
    BeamInputError too).
    """
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputTypeError(f"{name} = {shown(value)}: must be a number")
    try:
        v = float(value)
    except OverflowError:  # an int beyond 1.8e308
        v = math.inf
    if not math.isfinite(v):
        raise BeamInputError(f"{name} = {v}: must be finite")
    if v <= 0.0:
        raise BeamInputError(f"{name} = {v}: must be > 0")
    return v


def float_array(name: str, value: Any, unit: str) -> np.ndarray:
    """Return ``value`` as a flat float array of finite numbers.

    A BeamInputError names the field ``name``, the offending entry and the ``unit``.
    """
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__"):
        raise InputTypeError(f"{name} = {shown(value)}: must be a list of numbers ({unit})")
    for i, v in enumerate(value):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
            raise InputTypeError(f"{name}[{i}] = {shown(v)}: must be a number ({unit})")
    with np.errstate(over="ignore"):
        try:
            arr = np.array(value, dtype=float).reshape(-1)
        except OverflowError:  # an int beyond 1.8e308: reported as not finite below
            arr = np.array([float(v) if abs(v) < 2**1023 else math.inf for v in value])
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        i = int(bad[0])
        raise BeamInputError(f"{name}[{i}] = {arr[i]}: must be finite ({unit})")
    return arr


def check_representable(x: np.ndarray, w: np.ndarray, t: float, material: Material) -> None:
    """Reject units so extreme that derived quantities leave double precision's normal range.

    E I = E 2 w t^3 / 12, the mass and the load index L^2 / (E I) must be normal positive floats;
    otherwise they underflow to 0 or overflow (e.g. a thickness in mm read as m, cubed).
    """
    tiny, huge = np.finfo(float).tiny, np.finfo(float).max
    L = float(x[-1])
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        t3 = np.float64(t) ** 3
        EI = material.E_Pa * 2.0 * np.array([w.min(), w.max()]) * t3 / 12.0
        area = 2.0 * float(np.sum(0.5 * (w[1:] + w[:-1]) * np.diff(x)))
        mass = np.array([material.rho_kg_m3 * t * area])
        index = np.float64(L) ** 2 / EI
        # the section integrals form 2 w^3 and 2 w x^2 before the Gauss weights and rho t
        # scale them, and the links' inertias are of the order of m (L^2 + w^2 + t^2)
        wmax = np.float64(w.max())
        integrand = np.array([2.0 * wmax**3, 2.0 * wmax * np.float64(L) ** 2]) * 64.0
        inertia = mass * (np.float64(L) ** 2 + wmax**2 + np.float64(t) ** 2)
    fields_EI = f"thickness = {t!r} m, half_width = {w.min():g} ... {w.max():g} m, " \
        f"material.E = {material.E_Pa!r} Pa"
    checks = (
        (fields_EI, "E I = E 2 w t^3 / 12", EI, "N m^2"),
        (f"x (L = {L!r} m), half_width, thickness = {t!r} m, material.rho = "
         f"{material.rho_kg_m3!r} kg/m^3", "mass", mass, "kg"),
        (f"x (L = {L!r} m), {fields_EI}", "L^2 / (E I)", index, "1/N"),
        (f"x (L = {L!r} m), half_width = {w.min():g} ... {w.max():g} m", "the section "
         "integrands 2 w^3, 2 w L^2 (x 64)", integrand, "m^3"),
        (f"x (L = {L!r} m), half_width, thickness = {t!r} m, material.rho = "
         f"{material.rho_kg_m3!r} kg/m^3", "the links' inertia m (L^2 + w^2 + t^2)", inertia,
         "kg m^2"),
    )
    for fields, what, q, unit in checks:
        if not np.all(np.isfinite(q) & (q >= tiny) & (q <= huge)):
            raise BeamInputError(
                f"{fields}: {what} = {q.min():.3g} ... {q.max():.3g} {unit} is outside double "
                "precision's normal range (check the units: SI, m, Pa, kg/m^3)"
            )


def check_stations(x: np.ndarray, w: np.ndarray) -> None:
    """Check the stations ``x`` (m) and half-widths ``w`` (m) of a planform.

    ``x`` must not decrease from 0 to L, at most two vertices may share a station, and steps
    lie inside (0, L) with different half-widths (a repeated vertex is not a step and would
    only hide a typo).
    """
    dx = np.diff(x)
    bad = np.flatnonzero(dx < 0.0)
    if bad.size:
        i = int(bad[0]) + 1
        raise BeamInputError(
            f"x[{i}] = {x[i]} m: must not decrease (x[{i - 1}] = {x[i - 1]} m)"
        )
    same = np.flatnonzero(dx == 0.0)
    for j in same:
        i = int(j) + 1
        if j + 1 in same:
            raise BeamInputError(
                f"x[{i - 1}] = x[{i}] = x[{i + 1}] = {x[i]} m: at most two vertices may share a "
                "station (a width step)"
            )
        if x[i] == 0.0:
            raise BeamInputError(
                f"x[{i}] = {x[i]} m: a width step at the root is meaningless (the clamp holds "
                f"the first section); give one vertex at x = 0"
            )
        if i == x.size - 1:
            raise BeamInputError(
                f"x[{i}] = {x[i]} m: a width step at the tip is meaningless (the beam ends "
                f"there); give one vertex at x = L"
            )
        if w[i] == w[i - 1]:
            raise BeamInputError(
                f"x[{i}] = x[{i - 1}] = {x[i]} m with half_width {w[i]} m on both: a repeated "
                "vertex, not a width step (remove one, or give the two half-widths)"
            )


def thickness_law(x: np.ndarray, thickness: Any,
                  law: Any = None) -> tuple[float, np.ndarray | None]:
    """Return (t, law): the uniform thickness, or the largest of a varying law and the law, m.

    ``thickness`` is a number or a list aligned with the stations ``x`` (m); a list of equal
    entries is the number (so a uniform law computes exactly as today's thickness). ``law``
    is the stored law of a copy (``dataclasses.replace``): it must match ``thickness``.
    Errors name the field and the station: a thickness at or below zero anywhere (a law that
    reaches zero leaves the member without a section there), a list not aligned with x, or a
    jump at a width step (t is continuous).
    """
    if law is not None:
        arr = float_array("thickness_law", law, "m")
        if np.any(arr != arr.max()) and float(thickness) != float(arr.max()):
            raise BeamInputError(
                f"thickness = {thickness!r} m with thickness_law: must be the law's largest "
                f"value {float(arr.max())!r} m")
        thickness = arr
    # a ragged list is not asked for its ndim (numpy raises): float_array names it
    if not isinstance(thickness, (list, tuple, np.ndarray)) or (
            isinstance(thickness, np.ndarray) and thickness.ndim == 0):
        return finite_positive("thickness", thickness), None  # a number, or its type error
    t = float_array("thickness", thickness, "m")
    if t.size != x.size:
        raise BeamInputError(
            f"thickness has {t.size} entries: a thickness law must be aligned with x "
            f"({x.size} entries, one thickness per station)")
    bad = np.flatnonzero(t <= 0.0)
    if bad.size:
        i = int(bad[0])
        raise BeamInputError(
            f"thickness[{i}] = {t[i]} m at x = {x[i]} m: must be > 0 (a law reaching zero "
            "leaves no section there)")
    same = np.flatnonzero((np.diff(x) == 0.0) & (np.diff(t) != 0.0))
    if same.size:
        i = int(same[0]) + 1
        raise BeamInputError(
            f"thickness[{i}] = {t[i]} m at the width step x = {x[i]} m differs from "
            f"thickness[{i - 1}] = {t[i - 1]} m: the thickness is continuous (give one value)")
    if np.all(t == t[0]):
        return float(t[0]), None
    return float(t.max()), t
