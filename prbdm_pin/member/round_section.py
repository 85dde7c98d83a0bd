"""Round sections: a solid rod or a tube whose outer and inner diameters are laws of x.

The diameters D(x), d(x) are piecewise linear through the beam's stations (d = 0: solid). The
area A = pi (D^2 - d^2) / 4 and the area moments I_y = I_z = pi (D^4 - d^4) / 64 are then
polynomials of degree 2 and 4 between stations, so Gauss-Legendre quadrature integrates them
(and their moments in x) exactly. A circular section does not warp: its Saint-Venant constant
is the polar moment J = I_y + I_z = pi (D^4 - d^4) / 32.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..options.validate import check_size
from .checks import float_array

__all__ = ["RoundSection", "check_round_member", "round_area_m2", "round_area_moment_m4"]


def round_area_m2(outer_diameter_m, inner_diameter_m) -> np.ndarray:
    """Area pi (D^2 - d^2) / 4 of a round section, m^2 (diameters in m)."""
    D = np.asarray(outer_diameter_m, dtype=float)
    d = np.asarray(inner_diameter_m, dtype=float)
    return np.pi * (D * D - d * d) / 4.0


def round_area_moment_m4(outer_diameter_m, inner_diameter_m) -> np.ndarray:
    """Bending area moment I = pi (D^4 - d^4) / 64 about a diameter, m^4 (diameters in m)."""
    D = np.asarray(outer_diameter_m, dtype=float)
    d = np.asarray(inner_diameter_m, dtype=float)
    return np.pi * (D**4 - d**4) / 64.0


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class RoundSection:
    """Outer and inner diameters of a round member at the beam's stations ``Beam.x_m``.

    Attributes
    ----------
    outer_diameter_m : ndarray, shape (k,)
        Outer diameter D(x_k), m, > 0; linear between stations.
    inner_diameter_m : ndarray, shape (k,), optional
        Inner diameter d(x_k), m, in [0, D(x_k)); linear between stations. Omitted (None): a
        solid rod, stored as zeros.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> tube = pp.RoundSection(outer_diameter_m=[0.02, 0.02], inner_diameter_m=[0.016, 0.016])
    >>> tube.outer_diameter_m, tube.inner_diameter_m  # m
    (array([0.02, 0.02]), array([0.016, 0.016]))
    >>> rod = pp.RoundSection(outer_diameter_m=[0.02, 0.01])  # a solid rod: inner diameter zeros
    >>> rod.inner_diameter_m
    array([0., 0.])
    >>> pp.RoundSection(outer_diameter_m=[0.02, 0.02], inner_diameter_m=[0.02, 0.01])
    Traceback (most recent call last):
        ...
    prbdm_pin.errors.BeamInputError: section.inner_diameter[0] = 0.02 m (station ...
    """

    outer_diameter_m: np.ndarray
    inner_diameter_m: np.ndarray | None = field(default=None)

    kind = "round"

    def __post_init__(self) -> None:
        """Validate the diameters; an error names the field and the station index."""
        D = float_array("section.outer_diameter", self.outer_diameter_m, "m")
        if self.inner_diameter_m is None:
            d = np.zeros_like(D)
        else:
            d = float_array("section.inner_diameter", self.inner_diameter_m, "m")
        if d.size != D.size:
            raise BeamInputError(
                f"section.inner_diameter has {d.size} entries: must match "
                f"section.outer_diameter ({D.size} entries, one per station of x)")
        bad = np.flatnonzero(D <= 0.0)
        if bad.size:
            i = int(bad[0])
            raise BeamInputError(
                f"section.outer_diameter[{i}] = {D[i]} m (station {i}): must be > 0")
        bad = np.flatnonzero(d < 0.0)
        if bad.size:
            i = int(bad[0])
            raise BeamInputError(
                f"section.inner_diameter[{i}] = {d[i]} m (station {i}): must be >= 0")
        bad = np.flatnonzero(d >= D)
        if bad.size:
            i = int(bad[0])
            raise BeamInputError(
                f"section.inner_diameter[{i}] = {d[i]} m (station {i}): must be below "
                f"section.outer_diameter[{i}] = {D[i]} m (a tube needs a wall)")
        object.__setattr__(self, "outer_diameter_m", _readonly(D))
        object.__setattr__(self, "inner_diameter_m", _readonly(d))

    @property
    def solid(self) -> bool:
        """True when the inner diameter is zero everywhere (a rod, not a tube)."""
        return not np.any(self.inner_diameter_m)

    def to_dict(self) -> dict:
        """Return the beam-JSON ``"section"`` mapping (m); a rod leaves out the inner diameter."""
        out = {"kind": "round", "outer_diameter": [float(v) for v in self.outer_diameter_m]}
        if not self.solid:
            out["inner_diameter"] = [float(v) for v in self.inner_diameter_m]
        return out


def check_round_member(x: np.ndarray, w: np.ndarray, t, section) -> None:
    """Check a round member: section aligned with x, no width step, w = D / 2 and t = D."""
    if not isinstance(section, RoundSection):
        raise InputTypeError(
            f"section = {type(section).__name__}: must be a RoundSection or None")
    D = section.outer_diameter_m
    for i in (int(D.argmin()), int(D.argmax())):  # in 1e-5 ... 1e3 m: a size in mm is named
        check_size(f"section.outer_diameter[{i}]", float(D[i]))
    if D.size != x.size:
        raise BeamInputError(
            f"section.outer_diameter has {D.size} entries: must be aligned with x "
            f"({x.size} entries, one diameter per station)")
    if np.any(np.diff(x) == 0.0):
        i = int(np.flatnonzero(np.diff(x) == 0.0)[0]) + 1
        raise BeamInputError(
            f"x[{i}] = x[{i - 1}] = {x[i]} m: a round member has no width steps (the "
            "diameters are continuous); give each station once")
    if not (np.array_equal(w, 0.5 * D) and np.array_equal(np.broadcast_to(t, D.shape), D)):
        raise BeamInputError(
            "half_width and thickness of a round member must be the outer radius and "
            "diameter (build it with round_beam or the beam JSON \"section\")")
