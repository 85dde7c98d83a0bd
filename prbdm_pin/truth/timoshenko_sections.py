"""Section laws of a Timoshenko beam along x, and Cowper's shear coefficients.

Also the adapter from today's rectangular planform :class:`~prbdm_pin.member.geometry.Beam`.

A law is a number (uniform), a callable ``f(x_m) -> values`` or a pair ``(stations_m, values)``
linear between stations; :func:`section_law` turns each into a callable that checks its values
(finite, > 0) and names the law in the error.

Shear coefficients (Cowper 1966, "The shear coefficient in Timoshenko's beam theory", J. Appl.
Mech. 33, 335-340, Table 1), with nu Poisson's ratio:

- rectangle: kappa = 10 (1 + nu) / (12 + 11 nu)
- hollow circle, m = d / D: kappa = 6 (1 + nu) (1 + m^2)^2 /
  ((7 + 6 nu) (1 + m^2)^2 + (20 + 12 nu) m^2); m = 0 is the solid circle
  6 (1 + nu) / (7 + 6 nu), m -> 1 the thin tube 2 (1 + nu) / (4 + 3 nu).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..member.geometry import Beam
from ..member.section import area_moment_y_m4

__all__ = ["SHEAR_KINDS", "SectionLaws", "shear_coefficient", "section_law",
           "member_section_laws", "rectangle_section_laws"]

SHEAR_KINDS = ("rectangle", "solid_circle", "thin_tube", "tube")

Law = Callable[[np.ndarray], np.ndarray]


def shear_coefficient(kind: str, nu: float, inner_ratio: float = 0.0) -> float:
    """Cowper's shear coefficient kappa of a section (dimensionless).

    Parameters
    ----------
    kind : {"rectangle", "solid_circle", "thin_tube", "tube"}
        The section; ``"tube"`` takes ``inner_ratio``.
    nu : float
        Poisson's ratio, in (-1, 0.5).
    inner_ratio : float
        Inner over outer diameter d / D of a ``"tube"``, in [0, 1) (0: the solid circle).

    Returns
    -------
    float
        kappa, with kappa G A the shear stiffness (N) of the section.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> nu = 0.3
    >>> round(pp.shear_coefficient("rectangle", nu), 4), round(10 * (1 + nu) / (12 + 11 * nu), 4)
    (0.8497, 0.8497)
    >>> round(pp.shear_coefficient("solid_circle", nu), 4), round(6 * (1 + nu) / (7 + 6 * nu), 4)
    (0.8864, 0.8864)
    >>> pp.shear_coefficient("tube", nu, 0.0) == pp.shear_coefficient("solid_circle", nu)
    True
    """
    if not isinstance(kind, str):
        raise InputTypeError(f"kind = {kind!r}: must be one of {SHEAR_KINDS}")
    if kind not in SHEAR_KINDS:
        raise BeamInputError(f"kind = {kind!r}: must be one of {SHEAR_KINDS}")
    if not isinstance(nu, (int, float, np.floating)) or isinstance(nu, bool):
        raise InputTypeError(f"nu = {nu!r}: must be a number")
    if not -1.0 < float(nu) < 0.5:
        raise BeamInputError(f"nu = {nu!r}: must be in (-1, 0.5)")
    if kind == "rectangle":
        return 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)
    if kind == "thin_tube":
        return 2.0 * (1.0 + nu) / (4.0 + 3.0 * nu)
    m = 0.0 if kind == "solid_circle" else float(inner_ratio)
    if not 0.0 <= m < 1.0:
        raise BeamInputError(f"inner_ratio = {inner_ratio!r}: must be in [0, 1)")
    q = (1.0 + m * m) ** 2
    return 6.0 * (1.0 + nu) * q / ((7.0 + 6.0 * nu) * q + (20.0 + 12.0 * nu) * m * m)


def section_law(name: str, law) -> Law:
    """Return the law ``name`` as a callable of x (m) that checks its values are finite and > 0.

    Parameters
    ----------
    name : str
        The law's name with its unit (``"EI_Nm2"``...), used in errors.
    law : float, callable or (stations_m, values)
        A number (uniform), ``f(x_m)`` returning an array like ``x_m``, or a pair of equal-length
        sequences, linear between the ascending stations (m).
    """
    if callable(law):
        fn = law
    elif isinstance(law, (int, float, np.floating)) and not isinstance(law, bool):
        value = float(law)
        fn = lambda x: np.full(np.shape(x), value)  # noqa: E731
    elif isinstance(law, (tuple, list)) and len(law) == 2:
        xs = np.asarray(law[0], dtype=float)
        vs = np.asarray(law[1], dtype=float)
        if xs.ndim != 1 or xs.shape != vs.shape or xs.size < 2:
            raise BeamInputError(f"{name}: stations and values must be two 1D sequences of "
                                 f"equal length >= 2 (got shapes {xs.shape}, {vs.shape})")
        bad = np.flatnonzero(~(np.diff(xs) > 0.0))
        if bad.size or not np.all(np.isfinite(xs)):
            i = int(bad[0]) + 1 if bad.size else int(np.flatnonzero(~np.isfinite(xs))[0])
            raise BeamInputError(f"{name}: station {i} = {xs[i]!r} m: stations must be finite "
                                 "and strictly ascending")
        _check_values(name, xs, vs)
        fn = lambda x: np.interp(x, xs, vs)  # noqa: E731
    else:
        raise InputTypeError(f"{name} = {law!r}: must be a number, a callable of x (m) or a "
                             "pair (stations_m, values)")

    def checked(x: np.ndarray) -> np.ndarray:
        v = np.asarray(fn(x), dtype=float)
        if v.shape != np.shape(x):
            v = np.broadcast_to(v, np.shape(x)).astype(float)
        _check_values(name, x, v)
        return v

    return checked


def _check_values(name: str, x: np.ndarray, v: np.ndarray) -> None:
    bad = np.flatnonzero(~(np.isfinite(v) & (v > 0.0)))
    if bad.size:
        i = int(bad[0])
        xi = float(np.ravel(np.broadcast_to(x, np.shape(v)))[i])
        raise BeamInputError(f"{name} = {float(np.ravel(v)[i])!r} at x = {xi!r} m: must be "
                             "finite and > 0")


@dataclass(frozen=True)
class SectionLaws:
    """The four section laws of a plane Timoshenko beam.

    Each field is given as a number (uniform), a callable of x (m) or a pair
    (stations_m, values) linear between stations, and is stored as a checked callable of x
    (:func:`section_law`: a value that is not finite and > 0 is refused naming the law and x).

    Attributes
    ----------
    EI_Nm2 : callable
        Bending stiffness E I(x), N m^2.
    kappaGA_N : callable
        Shear stiffness kappa G A(x), N.
    rhoA_kg_m : callable
        Mass per length rho A(x), kg/m.
    rhoI_kg_m : callable
        Rotary inertia per length rho I(x) about the bending axis, kg m.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> laws = pp.SectionLaws(EI_Nm2=854.17, kappaGA_N=3.4e7, rhoA_kg_m=3.925,
    ...                       rhoI_kg_m=([0.0, 1.0], [3.3e-5, 1.6e-5]))  # a number, or a table
    >>> float(laws.EI_Nm2(0.5)), round(float(laws.rhoI_kg_m(0.5)), 8)  # linear between stations
    (854.17, 2.45e-05)
    >>> bad = pp.SectionLaws(EI_Nm2=-1.0, kappaGA_N=3.4e7, rhoA_kg_m=3.925, rhoI_kg_m=3.3e-5)
    >>> bad.EI_Nm2(0.5)  # a law is checked where it is evaluated
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: EI_Nm2 = -1.0 at x = 0.5 m: must be finite and > 0
    """

    EI_Nm2: Law
    kappaGA_N: Law
    rhoA_kg_m: Law
    rhoI_kg_m: Law

    def __post_init__(self) -> None:
        """Turn every law into a checked callable (errors name the field)."""
        for name in ("EI_Nm2", "kappaGA_N", "rhoA_kg_m", "rhoI_kg_m"):
            object.__setattr__(self, name, section_law(name, getattr(self, name)))


def member_section_laws(beam: Beam) -> SectionLaws:
    """Return a member's laws for bending about y: the planform's rectangle or a round section.

    The stiffness and inertias come from :func:`~prbdm_pin.member.section_law.section_properties`
    (the one place every model reads); the shear stiffness kappa G A from Cowper's coefficient of
    the section (rectangle; a round member's hollow circle at each station's d / D, the solid
    circle at d = 0). A section table carries no shear stiffness, so it is refused by name.

    Parameters
    ----------
    beam : Beam

    Returns
    -------
    SectionLaws
    """
    if not isinstance(beam, Beam):
        raise InputTypeError(f"beam = {beam!r}: must be a prbdm_pin.Beam")
    if beam.section is None:
        return rectangle_section_laws(beam)
    from ..member.round_section import RoundSection
    from ..member.section_law import section_properties

    if not isinstance(beam.section, RoundSection):
        raise BeamInputError("beam.section: a section table gives no shear stiffness (kappa G "
                             "A): the Timoshenko truth and its criterion take a planform or a "
                             "round member")
    mat, sec = beam.material, beam.section
    D = sec.outer_diameter_m
    d = np.zeros_like(D) if sec.inner_diameter_m is None else sec.inner_diameter_m

    def kappa(x):
        ratio = np.interp(x, beam.x_m, d) / np.interp(x, beam.x_m, D)
        return np.vectorize(lambda r: shear_coefficient("tube", mat.nu, float(r)))(ratio)

    def area(x):
        return section_properties(beam, x).rhoA_kg_m / mat.rho_kg_m3

    return SectionLaws(
        EI_Nm2=lambda x: section_properties(beam, x).EI_y_Nm2,
        kappaGA_N=lambda x: kappa(x) * mat.G_Pa * area(x),
        rhoA_kg_m=lambda x: section_properties(beam, x).rhoA_kg_m,
        rhoI_kg_m=lambda x: section_properties(beam, x).rhoI_y_kg_m,
    )


def rectangle_section_laws(beam: Beam) -> SectionLaws:
    """Return the laws of a planform beam's rectangle b(x) = 2 w(x) by t(x), bending about y.

    E I_y = E b t^3 / 12, kappa G A with Cowper's rectangle kappa, rho A = rho b t,
    rho I_y = rho b t^3 / 12. At a width step w is right-continuous; the element edges sit on
    the stations, so each element sees one side only.

    Parameters
    ----------
    beam : Beam

    Returns
    -------
    SectionLaws

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.05, 0.025], thickness_m=0.01)  # a taper
    >>> laws = pp.rectangle_section_laws(beam)
    >>> b = 0.075  # m, the width at x = 0.5 m
    >>> round(float(laws.EI_Nm2(0.5)), 2), round(205e9 * b * 0.01**3 / 12, 2)  # N m^2, E b t^3 / 12
    (1281.25, 1281.25)
    >>> kappa = 10 * (1 + 0.28) / (12 + 11 * 0.28)  # Cowper's rectangle
    >>> G = 205e9 / (2 * (1 + 0.28))  # Pa
    >>> round(float(laws.kappaGA_N(0.5)) / 1e6, 3), round(kappa * G * b * 0.01 / 1e6, 3)  # MN
    (50.978, 50.978)
    """
    if not isinstance(beam, Beam):
        raise InputTypeError(f"beam = {beam!r}: must be a prbdm_pin.Beam")
    mat = beam.material
    kappa = shear_coefficient("rectangle", mat.nu)

    def b(x):
        return 2.0 * np.asarray(beam.half_width_at(x), dtype=float)

    def t(x):
        return np.asarray(beam.thickness_at(x), dtype=float)

    return SectionLaws(
        EI_Nm2=lambda x: mat.E_Pa * area_moment_y_m4(b(x), t(x)),
        kappaGA_N=lambda x: kappa * mat.G_Pa * b(x) * t(x),
        rhoA_kg_m=lambda x: mat.rho_kg_m3 * b(x) * t(x),
        rhoI_kg_m=lambda x: mat.rho_kg_m3 * area_moment_y_m4(b(x), t(x)),
    )
