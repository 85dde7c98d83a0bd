"""Design variables: which quantities of a beam an optimiser moves, as a vector in SI units.

``Design(beam, ("thickness", "half_width[2]", "x[3]", "E", "rho"))`` names the quantities;
``values`` reads them from the beam, ``beam_at(p)`` writes a vector back into a copy of it and
``bounds`` keeps every vector inside the box a valid beam of the same planform topology.

Names and what they move:

* ``thickness`` (m), ``E`` (Pa), ``rho`` (kg/m^3), ``nu`` (1): the uniform thickness and the
  material constants.
* ``half_width[i]`` (m): the half-width of vertex i. The planform stays symmetric about the x
  axis: the vertex and its mirror image move together. At a width step (two vertices at one
  station) it moves that side of the step only.
* ``x[i]`` (m): the station of interior vertex i. At a width step it moves the step, both of its
  vertices together (naming both of them is refused). The root x[0] = 0 (the clamp) and the tip
  station (the length L) are not design variables.

The bounds are a box in which every vector is a valid beam with the same vertex structure:
positive thickness, moduli and half-widths, nu in (-1, 0.5), a station strictly between its
neighbours' and a step keeping its direction (the narrow side stays narrow). Where two varied
quantities constrain each other (adjacent varied stations, both sides of a step) the box splits
the gap between their current values at the midpoint, so no vector inside it reorders them.
Bounds are open at these limits: ``beam_at`` refuses a vector on or outside them.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace

import numpy as np

from ..errors import BeamInputError, InputTypeError
from .geometry import Beam

__all__ = ["Design", "DESIGN_UNITS"]

DESIGN_UNITS = {"thickness": "m", "E": "Pa", "rho": "kg/m^3", "nu": "1", "half_width": "m",
                "x": "m"}
_SCALAR = ("thickness", "E", "rho", "nu")
_INDEXED = re.compile(r"^(half_width|x)\[(\d+)\]$")


def _parse(beam: Beam, name: object) -> tuple[str, int]:
    """(kind, vertex index) of one variable name; index -1 for the scalars."""
    if not isinstance(name, str):
        raise BeamInputError(f"design variable {name!r}: must be a string such as 'thickness', "
                             "'half_width[2]' or 'x[3]'")
    if name in _SCALAR:
        return name, -1
    m = _INDEXED.match(name)
    if m is None:
        raise BeamInputError(
            f"design variable {name!r}: unknown; use thickness, E, rho, nu, half_width[i] or "
            "x[i] (i a vertex index)")
    kind, i = m.group(1), int(m.group(2))
    n = beam.x_m.size
    if i >= n:
        raise BeamInputError(f"design variable {name!r}: vertex {i} does not exist (the beam "
                             f"{beam.name!r} has vertices 0..{n - 1})")
    if kind == "x" and i == 0:
        raise BeamInputError(f"design variable {name!r}: x[0] = 0 is the clamped root, not a "
                             "design variable")
    if kind == "x" and i == n - 1:
        raise BeamInputError(f"design variable {name!r}: x[{i}] is the tip station (the length "
                             "L), not a design variable; vary the interior stations")
    return kind, i


def step_partner(beam: Beam, i: int) -> int | None:
    """Return the other vertex of the width step vertex ``i`` belongs to, or None."""
    x = beam.x_m
    if i + 1 < x.size and x[i + 1] == x[i]:
        return i + 1
    if i > 0 and x[i - 1] == x[i]:
        return i - 1
    return None


@dataclass(frozen=True, eq=False)
class Design:
    """Named design variables of a beam and the map from a vector of their values to a beam.

    Parameters
    ----------
    beam : Beam
        The current design; ``values`` are read from it and ``beam_at`` copies it.
    variables : tuple of str
        Names (see the module docstring): ``thickness``, ``E``, ``rho``, ``nu``,
        ``half_width[i]``, ``x[i]``; each at most once.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 0.5, 1.0], half_width_m=[0.03, 0.025, 0.02], thickness_m=0.01)
    >>> design = pp.Design(beam, ("thickness", "half_width[1]", "E"))
    >>> design.size, design.units
    (3, ('m', 'm', 'Pa'))
    >>> design.values.round(4)[:2], float(design.values[2])  # m, m, Pa
    (array([0.01 , 0.025]), 205000000000.0)
    >>> thicker = design.beam_at([0.012, 0.025, beam.material.E_Pa])
    >>> thicker.thickness_m, round(thicker.mass_kg / beam.mass_kg, 4)  # the mass scales with t
    (0.012, 1.2)
    """

    beam: Beam
    variables: tuple[str, ...]

    def __post_init__(self) -> None:
        """Check the beam and the names, and parse every name once."""
        if not isinstance(self.beam, Beam):
            raise InputTypeError(f"beam = {self.beam!r}: must be a prbdm_pin.Beam")
        self.beam.rectangle_only("design variations")  # its variables are w, t, x of a planform
        if isinstance(self.variables, str) or not hasattr(self.variables, "__iter__"):
            raise BeamInputError(f"variables = {self.variables!r}: must be a sequence of names "
                                 "such as ('thickness', 'half_width[2]')")
        names = tuple(self.variables)
        if not names:
            raise BeamInputError("variables = (): name at least one design variable")
        parsed, seen = [], {}
        for name in names:
            kind, i = _parse(self.beam, name)
            # a step's station is one quantity, whichever of its two vertices names it
            key = (kind, i if kind != "x" else min(i, step_partner(self.beam, i) or i))
            if key in seen:
                raise BeamInputError(f"design variable {name!r}: the same quantity as "
                                     f"{seen[key]!r} (named twice)")
            seen[key] = name
            parsed.append((kind, i))
        object.__setattr__(self, "variables", names)
        object.__setattr__(self, "_parsed", tuple(parsed))

    # ------------------------------------------------------------------------------------------
    @property
    def names(self) -> tuple[str, ...]:
        """The variable names, in vector order."""
        return self.variables

    @property
    def kinds(self) -> tuple[tuple[str, int], ...]:
        """(kind, vertex index) of every variable; the index is -1 for the scalars."""
        return self._parsed

    @property
    def size(self) -> int:
        """Number of design variables."""
        return len(self.variables)

    @property
    def units(self) -> tuple[str, ...]:
        """SI unit of every variable."""
        return tuple(DESIGN_UNITS[k] for k, _ in self._parsed)

    @property
    def values(self) -> np.ndarray:
        """The current design's values (SI units), shape (size,)."""
        b, mat = self.beam, self.beam.material
        t_u = b.uniform_thickness_m("design variations")
        scalar = {"thickness": t_u, "E": mat.E_Pa, "rho": mat.rho_kg_m3, "nu": mat.nu}
        out = np.array([scalar[k] if i < 0 else (b.half_width_m if k == "half_width"
                                                 else b.x_m)[i] for k, i in self._parsed])
        out.setflags(write=False)
        return out

    @property
    def scales(self) -> np.ndarray:
        """A scale of every variable (SI units), shape (size,), for finite-difference steps.

        The value itself for thickness, E and rho; 0.1 for nu; for a half-width the smallest of
        the half-width, the adjacent vertex intervals and, at a width step, the step's jump; for a
        station the shorter adjacent vertex interval (the distances over which the planform, and
        the mesh that follows it, change character).
        """
        b = self.beam
        x, w = b.x_m, b.half_width_m
        gaps = np.diff(x)
        out = np.empty(self.size)
        for row, (kind, i) in enumerate(self._parsed):
            if kind == "nu":
                out[row] = 0.1
            elif i < 0:
                out[row] = self.values[row]
            elif kind == "half_width":
                # the outline next to the vertex moves across elements as small as the
                # adjacent vertex intervals (the mesh follows every vertex)
                j = step_partner(b, i)
                near = [g for g in (gaps[i - 1] if i > 0 else 0.0,
                                    gaps[i] if i < gaps.size else 0.0) if g > 0]
                out[row] = min([w[i], *near] + ([abs(w[i] - w[j])] if j is not None else []))
            else:
                out[row] = min(gaps[:i][gaps[:i] > 0][-1], gaps[i:][gaps[i:] > 0][0])
        out.setflags(write=False)
        return out

    @property
    def bounds(self) -> np.ndarray:
        """Open bounds (SI units), shape (size, 2): lower and upper value of every variable.

        See the module docstring for how they are set. The array is a sequence of pairs, as
        ``scipy.optimize.minimize(bounds=...)`` takes.
        """
        b = self.beam
        x, w = b.x_m, b.half_width_m
        varied_x = {i for k, i in self._parsed if k == "x"}
        varied_x |= {step_partner(b, i) for i in varied_x} - {None}
        varied_w = {i for k, i in self._parsed if k == "half_width"}
        out = np.empty((self.size, 2))
        for row, (kind, i) in enumerate(self._parsed):
            if kind == "nu":
                out[row] = (-1.0, 0.5)
            elif kind in ("thickness", "E", "rho"):
                out[row] = (0.0, np.inf)
            elif kind == "x":
                lo_i = i - 1 if step_partner(b, i) != i - 1 else i - 2
                hi_i = i + 1 if step_partner(b, i) != i + 1 else i + 2
                lo, hi = x[lo_i], x[hi_i]
                if lo_i in varied_x:
                    lo = 0.5 * (lo + x[i])
                if hi_i in varied_x:
                    hi = 0.5 * (hi + x[i])
                out[row] = (lo, hi)
            else:
                j = step_partner(b, i)
                if j is None:
                    out[row] = (0.0, np.inf)
                    continue
                other = w[j] if j not in varied_w else 0.5 * (w[j] + w[i])
                out[row] = (0.0, other) if w[i] < w[j] else (other, np.inf)
        out.setflags(write=False)
        return out

    # ------------------------------------------------------------------------------------------
    def check(self, p: np.ndarray) -> np.ndarray:
        """Return ``p`` as a float vector after checking it against the bounds.

        Parameters
        ----------
        p : numpy.ndarray
            Design vector (SI units, see ``units``), shape (size,).

        Returns
        -------
        numpy.ndarray
            ``p`` as floats, shape (size,).

        Raises
        ------
        BeamInputError
            Wrong length, or a value not finite or not strictly inside ``bounds`` (named).
        """
        a = np.asarray(p, dtype=float) if not isinstance(p, (str, bytes)) else None
        if a is None or a.shape != (self.size,):
            raise BeamInputError(f"design vector {p!r}: must be {self.size} numbers "
                                 f"({', '.join(self.variables)})")
        bounds = self.bounds
        for name, unit, v, (lo, hi) in zip(self.variables, self.units, a, bounds, strict=True):
            if not np.isfinite(v):
                raise BeamInputError(f"design variable {name} = {v} {unit}: must be finite")
            if not lo < v < hi:
                raise BeamInputError(f"design variable {name} = {v:.9g} {unit}: must lie in "
                                     f"({lo:.9g}, {hi:.9g}) {unit} (bounds of this design)")
        return a

    def beam_at(self, p: np.ndarray) -> Beam:
        """Return the beam with the design variables set to ``p``, everything else as in ``beam``.

        Parameters
        ----------
        p : numpy.ndarray
            Design vector (SI units, see ``units``), shape (size,).

        Returns
        -------
        Beam
            A new beam; ``beam`` itself is not changed.

        Raises
        ------
        BeamInputError
            A value not finite or not strictly inside ``bounds`` (named), or a beam the
            ``Beam`` checks refuse.
        """
        a = self.check(p)
        b = self.beam
        x, w = b.x_m.copy(), b.half_width_m.copy()
        t = b.uniform_thickness_m("design variations")
        mat = {}
        for (kind, i), v in zip(self._parsed, a, strict=True):
            if kind == "thickness":
                t = float(v)
            elif kind in ("E", "rho", "nu"):
                mat[{"E": "E_Pa", "rho": "rho_kg_m3", "nu": "nu"}[kind]] = float(v)
            elif kind == "half_width":
                w[i] = v
            else:
                x[i] = v
                j = step_partner(b, i)
                if j is not None:
                    x[j] = v
        return Beam(x, w, t, replace(b.material, **mat), b.tip_force_N, b.name, b.description)
