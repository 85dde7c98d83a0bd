"""The beam: planform and thickness of a clamped-free member, and its beam-JSON mapping.

Conventions: the beam axis is x with the clamped root at x = 0 and the tip at x = L; the
planform is symmetric about the x axis with a piecewise-linear half-width w(x) through the
vertices (x_k, w_k); the thickness t is uniform or a piecewise-linear law t(x) through the same
stations (x_k, t_k), and bending is out of plane (deflection along z).
Two vertices may share a station x_k (never more, and never at the root or the tip): a width step,
where the half-width jumps; w(x) is right-continuous there (the tip-side value).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field

import numpy as np

from ..errors import BeamInputError
from ..io.jsonfile import field_str
from ..options.validate import check_planform, check_type
from .beam_dict import beam_to_dict
from .checks import check_representable, check_stations, float_array, thickness_law
from .material import Material
from .round_section import RoundSection, check_round_member
from .section_table import SectionTable, check_table_member

__all__ = ["Beam", "beam_to_dict"]


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class Beam:
    """A clamped-free compliant member: symmetric planform, uniform or piecewise-linear thickness.

    Attributes
    ----------
    x_m : ndarray, shape (k,)
        Planform vertex stations in m; x_m[0] = 0 (the clamp), non-decreasing, x_m[-1] = L. Two
        equal stations x_k = x_(k+1) inside (0, L) are a width step: the half-width jumps from
        w_k to w_(k+1) there.
    half_width_m : ndarray, shape (k,)
        Half-width w(x_k) in m (> 0); the width is 2 w, linear between vertices.
    thickness_m : float or array_like
        Thickness t in m: a number (uniform), or a list aligned with ``x_m`` (a piecewise-linear
        law t(x_k), > 0 at every station). A list of equal entries is the uniform thickness
        (stored as the number, so it computes exactly as a number does). For a varying law,
        ``thickness_m`` holds its largest value after construction and the law is in
        ``thickness_law_m``; a width step is not a thickness step (t is continuous).

    Sizes lie in [1e-5, 1e3] m and the planform is at most 20 times as wide as long
    (:func:`prbdm_pin.validate.check_planform`): outside, the error names the field and the
    unit slip it suggests (a thickness in mm, E in GPa).
    material : Material
    tip_force_N : ndarray, shape (3,)
        The load case: a force at the tip in world axes, N.
    name, description : str
    thickness_law_m : ndarray, shape (k,), or None
        The thickness at the stations ``x_m``, m, when it varies; None when uniform. Given
        directly (e.g. by :func:`dataclasses.replace`) it must agree with ``thickness_m``.
    section : RoundSection, SectionTable or None
        None: the planform rectangle 2 w(x) x t(x). A :class:`RoundSection`: a rod or tube
        whose section law replaces the rectangle (build it with
        :func:`~prbdm_pin.member.section_member.round_beam`); its half-width is then the outer
        radius and its thickness the outer diameter (so the strain sensor's half thickness is
        the outer radius), the stations have no width steps, and every model that needs a
        rectangle (the plate, the solid, the elastica's anticlastic strips) refuses it by name
        (:meth:`rectangle_only`). A :class:`SectionTable`: section properties at the stations
        (build it with :func:`~prbdm_pin.member.section_member.table_beam`); its half-width
        and thickness are those of the square of the same E I_y / E (side (12 E I_y / E)^(1/4),
        clipped into the size range), for the size checks only: :meth:`half_width_at` and
        :meth:`thickness_at` refuse it.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> beam.length_m, beam.planform_area_m2  # m, m^2
    (1.0, 0.05)
    >>> round(beam.mass_kg, 4), round(beam.material.rho_kg_m3 * 1.0 * 0.05 * 0.01, 4)  # rho b t L
    (3.925, 3.925)
    >>> round(beam.root_EI_Nm2, 2), round(beam.material.E_Pa * 0.05 * 0.01**3 / 12, 2)  # E b t^3/12
    (854.17, 854.17)
    >>> taper = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.05, 0.025], thickness_m=0.01)
    >>> round(taper.planform_area_m2, 4), round((0.1 + 0.05) / 2 * 1.0, 4)  # a trapezoid, m^2
    (0.075, 0.075)
    """

    x_m: np.ndarray
    half_width_m: np.ndarray
    thickness_m: float
    material: Material = field(default_factory=Material)
    tip_force_N: np.ndarray = field(default_factory=lambda: np.zeros(3))
    name: str = "beam"
    description: str = ""
    thickness_law_m: np.ndarray | None = None
    section: RoundSection | SectionTable | None = None

    def __post_init__(self) -> None:
        """Validate the fields (errors name the field and the value); freeze the arrays."""
        field_str("name", self.name)
        field_str("description", self.description)
        x = float_array("x", self.x_m, "m")
        w = float_array("half_width", self.half_width_m, "m")
        if x.size < 2:
            raise BeamInputError(f"x has {x.size} entries: needs at least 2 (root and tip)")
        if w.size != x.size:
            raise BeamInputError(
                f"half_width has {w.size} entries: must match x ({x.size} entries)"
            )
        if x[0] != 0.0:
            raise BeamInputError(f"x[0] = {x[0]} m: must be 0 (the clamped root)")
        check_stations(x, w)
        bad = np.flatnonzero(w <= 0.0)
        if bad.size:
            i = int(bad[0])
            raise BeamInputError(f"half_width[{i}] = {w[i]} m: must be > 0")
        t, law = thickness_law(x, self.thickness_m, self.thickness_law_m)
        if isinstance(self.section, SectionTable):  # w, t: the equivalent square's, unchecked
            check_table_member(x, self.section)
        elif self.section is not None:  # first: its errors name the diameters, not w and t
            check_round_member(x, w, t if law is None else law, self.section)
        for tk in (t,) if law is None else (float(law.min()), t):
            check_planform(x, w, tk)  # sizes in 1e-5 ... 1e3 m: a size in mm is named
        check_type("material", self.material, Material)
        f = float_array("tip_force", self.tip_force_N, "N")
        if f.size != 3:
            raise BeamInputError(f"tip_force has {f.size} entries: must be [Fx, Fy, Fz] in N")
        for tk in (t,) if law is None else (float(law.min()), t):
            check_representable(x, w, tk, self.material)
        object.__setattr__(self, "x_m", _readonly(x))
        object.__setattr__(self, "half_width_m", _readonly(w))
        object.__setattr__(self, "thickness_m", t)
        object.__setattr__(self, "thickness_law_m", None if law is None else _readonly(law))
        object.__setattr__(self, "tip_force_N", _readonly(f))
        steps = np.flatnonzero(np.diff(x) == 0.0)
        steps.setflags(write=False)
        object.__setattr__(self, "_steps", steps)  # read in the fit's inner loop

    # Derived geometry -------------------------------------------------------------------------
    @property
    def length_m(self) -> float:
        """Beam length L in m."""
        return float(self.x_m[-1])

    @property
    def step_index(self) -> np.ndarray:
        """Indices k of the width steps, x_m[k] == x_m[k + 1] (int, possibly empty)."""
        return self._steps

    @property
    def intervals_m(self) -> tuple[np.ndarray, np.ndarray]:
        """Starts and ends (m) of the vertex intervals of positive length, where w is linear.

        The zero-length "intervals" of width steps are left out.
        """
        keep = np.diff(self.x_m) > 0.0
        return self.x_m[:-1][keep], self.x_m[1:][keep]

    def half_width_at(self, x_m: np.ndarray | float, side: str = "right") -> np.ndarray:
        """Half-width w(x) in m at stations ``x_m`` (m), linear between vertices.

        At a width step w is right-continuous (``side="right"``, the tip-side value); ``"left"``
        gives the root-side limit there. Elsewhere both are the same.
        """
        if side not in ("left", "right"):
            raise ValueError(f"side = {side!r}: must be 'left' or 'right'")
        self._not_table("half_width")
        w = np.interp(x_m, self.x_m, self.half_width_m)
        k = self.step_index
        if not k.size:
            return w
        # np.interp leaves a repeated abscissa to its implementation: set it explicitly
        x = np.asarray(x_m, dtype=float)
        w = np.array(w, dtype=float)
        for xs, ws in zip(self.x_m[k], self.half_width_m[k + 1 if side == "right" else k],
                          strict=True):
            w[x == xs] = ws
        return w[()] if w.ndim == 0 else w

    def thickness_at(self, x_m: np.ndarray | float) -> np.ndarray | float:
        """Thickness t(x) in m at stations ``x_m`` (m): linear between stations, continuous."""
        self._not_table("thickness")
        if self.thickness_law_m is None:
            return self.thickness_m + 0.0 * np.asarray(x_m, dtype=float)
        return np.interp(x_m, self.x_m, self.thickness_law_m)

    def _not_table(self, what: str) -> None:
        if isinstance(self.section, SectionTable):
            raise BeamInputError(
                f"section = {{'kind': 'table', ...}}: a section table has no {what} (it gives "
                "stiffnesses and inertias only); this use needs a planform or round member")

    def rectangle_only(self, what: str) -> None:
        """Refuse a round or table member for ``what``, a model of the planform rectangle only.

        Raises
        ------
        BeamInputError
            When ``section`` is set (the message names the section and ``what``).
        """
        if self.section is not None:
            raise BeamInputError(
                f"section = {{'kind': {self.section.kind!r}, ...}}: {what} takes the planform "
                "rectangle (half_width, thickness) only; a round or table member takes the 1D beam "
                "truth (prbdm truth --model beam, prbdm fit --truth-model beam) and the planar "
                "and spatial chains; a round member's 3D solid is prbdm_pin.round_solid_modes")

    def uniform_thickness_m(self, what: str) -> float:
        """Return the uniform thickness t in m; a thickness law is refused for ``what``.

        Parameters
        ----------
        what : str
            The model that takes one thickness only (named in the error).

        Raises
        ------
        BeamInputError
            When the thickness varies along x, or the member has a section (round or table:
            :meth:`rectangle_only`).
        """
        self.rectangle_only(what)
        if self.thickness_law_m is not None:
            law = self.thickness_law_m
            raise BeamInputError(
                f"thickness = {float(law.min()):g} ... {float(law.max()):g} m varies along x: "
                f"{what} takes a uniform thickness only (the 1D beam truth, the plate, the "
                "solid, the elastica and the chains take the law)")
        return self.thickness_m

    def area_moment_at(self, x_m: np.ndarray | float, side: str = "right") -> np.ndarray:
        """Bending area moment I_yy(x) = 2 w(x) t(x)^3 / 12 in m^4.

        ``x_m`` in m; ``side`` as in :meth:`half_width_at`. A round member's is
        pi (D^4 - d^4) / 64, a table's E I_y / E
        (:func:`~prbdm_pin.member.section_law.section_properties`).
        """
        if self.section is not None:
            from .section_law import section_properties

            return section_properties(self, x_m).EI_y_Nm2 / self.material.E_Pa
        if self.thickness_law_m is None:
            return 2.0 * self.half_width_at(x_m, side) * self.thickness_m**3 / 12.0
        return 2.0 * self.half_width_at(x_m, side) * self.thickness_at(x_m) ** 3 / 12.0

    @property
    def planform_area_m2(self) -> float:
        """Planform area in m^2.

        Exact for the piecewise-linear outline; a step's zero-length interval adds nothing.
        """
        return float(2.0 * np.trapezoid(self.half_width_m, self.x_m))

    @property
    def mass_kg(self) -> float:
        """Total mass in kg (exact for a thickness law: 2 w t is quadratic between stations).

        A round member's rho A is quadratic between stations too (a table's linear): Simpson's
        rule is exact.
        """
        if self.section is not None:
            from .section_law import section_properties

            x = np.concatenate([self.x_m, 0.5 * (self.x_m[:-1] + self.x_m[1:])])
            a = section_properties(self, x).rhoA_kg_m
            k = self.x_m.size
            h = np.diff(self.x_m)
            return float(np.sum(h * (a[:k - 1] + 4.0 * a[k:] + a[1:k]) / 6.0))
        if self.thickness_law_m is None:
            return self.planform_area_m2 * self.thickness_m * self.material.rho_kg_m3
        w, t, h = self.half_width_m, self.thickness_law_m, np.diff(self.x_m)
        # Simpson's rule is exact for the quadratic w t on each interval
        wt = (w[:-1] * t[:-1] + w[1:] * t[1:] + (w[:-1] + w[1:]) * (t[:-1] + t[1:])) / 6.0
        return float(2.0 * np.sum(h * wt) * self.material.rho_kg_m3)

    @property
    def root_EI_Nm2(self) -> float:
        """Bending stiffness E I at the root section, N m^2 (the load index uses it)."""
        return float(self.material.E_Pa * self.area_moment_at(0.0))

    def load_index(self, force_N: float | None = None) -> float:
        """Load index P L^2 / (E I_root) of a tip force magnitude (default: this beam's load)."""
        P = float(np.linalg.norm(self.tip_force_N)) if force_N is None else float(force_N)
        return P * self.length_m**2 / self.root_EI_Nm2

    def kirchhoff_warnings(self, modes: int = 5, tol_pct: float = 1.0) -> tuple[str, ...]:
        """Where a Kirchhoff plate (the ``plate`` truths) misrepresents this beam, as warnings.

        See :func:`~prbdm_pin.member.kirchhoff.kirchhoff_warnings` (``modes``: bending modes
        the truth selects; ``tol_pct``: the estimated error, %, that triggers a warning).
        """
        from .kirchhoff import kirchhoff_warnings

        return kirchhoff_warnings(self, modes, tol_pct)

    def with_tip_force(self, tip_force_N: np.ndarray) -> Beam:
        """Return a copy with another tip force (N)."""
        return Beam(
            self.x_m, self.half_width_m, self.thickness_m, self.material,
            np.asarray(tip_force_N, dtype=float), self.name, self.description,
            self.thickness_law_m, self.section,
        )

    def fingerprint(self) -> str:
        """Return a stable SHA-256 hex digest of the beam's physical content (for caches)."""
        import hashlib

        d = beam_to_dict(self)
        d.pop("name", None)
        d.pop("description", None)
        return hashlib.sha256(json.dumps(d, sort_keys=True).encode()).hexdigest()
