"""What a fit matches: the truth's frequencies and static load cases (FitTarget).

The target comes from a truth computation or from a PRBDM taken as its own truth.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..options.checks import check_float, shown
from ..options.validate import check_type, real_vector
from .load_case import LoadCase, read_only
from .mode_shapes import ModeShapes, truth_mode_shapes

if TYPE_CHECKING:
    from ..truth.request import TruthRequest

__all__ = ["LoadCase", "FitTarget", "target_from_truth", "model_target", "read_only"]


@dataclass(frozen=True, eq=False)
class FitTarget:
    """What a fit needs from a truth.

    Attributes
    ----------
    omega_truth_rad_s : ndarray, shape (N,)
        Truth bending frequencies, ascending, rad/s.
    tip_force_N : ndarray, shape (3,)
        The static load case: a force at the tip, N.
    tip_position_m, tip_displacement_m : ndarray, shape (3,), or None
        Truth large-deflection tip position and displacement under ``tip_force_N``, m.
    mac : ndarray, shape (N,), or None
        MAC of each truth mode with a beam bending mode (recorded, not fitted).
    source : str
        Where the numbers come from (e.g. ``"plate, level 3, selection paper"``).
    labels : tuple of str, or None
        Each truth mode's shape label (``"bending"``, ``"chordwise"``, ``"mixed"``, ...).
    extra_loads : tuple of LoadCase
        Further load cases (e.g. a load sweep). The deflection objective averages the tip error
        of every case, each normalised by its own truth tip position or displacement; with none,
        it is the paper's single-load Eq. 19. n frequencies and one planar tip cannot fix the
        2n lengths and springs of a ``joint`` model for n >= 2; more load cases can.
    truth_request : TruthRequest or None
        The ``compute_truth`` call the numbers came from, when they came from one.
    static_theory_gap_pct : float or None
        100 (u_1D / u_truth - 1): the 1D beam's linear tip deflection against the truth model's
        under the same small load, in % (the gap between the two theories; None when unknown).
    all_omega_rad_s : ndarray, shape (K,), or None
        Every mode the truth computed, ascending, rad/s (bending or not): what a spatial fit
        selects its modes of each kind from.
    all_labels : tuple of str, or None
        The label of each of them (``bending``, ``torsion``, ``in-plane``, ``chordwise``, ...).
    point_gains : tuple of (str, ndarray (K,)), or None
        The z amplitude of each of those modes, mass-normalised (1/sqrt(kg)), at named points of
        the tip (``tip``, ``tip_corner_left``, ``tip_corner_right``): what a spatial fit's
        ``gain_points`` term matches (:func:`prbdm_pin.fitting.spatial_gains.with_point_gains`).
    tip_moment_Nm : ndarray, shape (3,), or None
        A tip moment besides the force, N m, world axes (the spatial deflection objective).
    load_point : str
        Where ``tip_force_N`` acts: ``tip`` (the centre of the free end), ``tip_corner_left``
        or ``tip_corner_right`` (:mod:`prbdm_pin.truth.corner_static`).
    tip_twist_rad : float or None
        The truth's tip twist under the load, rad (the angle of the tip's corner-to-corner
        line to the world y axis in the y-z plane): with the tip, what a spatial deflection
        fit matches (:mod:`prbdm_pin.fitting.spatial_deflection`).
    mode_shapes : ModeShapes or None
        Every truth mode's deflection and twist along the span: what a spatial fit's result
        pairs its modes by (MAC, :mod:`prbdm_pin.fitting.mode_shapes`); None: by order.
    gravity_m_s2 : ndarray, shape (3,), or None
        The gravity the truth was computed in, m/s^2, member axes (g_y = 0): its frequencies
        are about its sag and its tips under the loads plus its weight, and a fit evaluates
        the chain in the same gravity (:mod:`prbdm_pin.fitting.gravity_fit`).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> EI = beam.material.E_Pa * 0.05 * 0.01**3 / 12  # N m^2
    >>> rho_A = beam.material.rho_kg_m3 * 0.05 * 0.01  # kg/m
    >>> w = np.array([1.8751041, 4.6940911])**2 * np.sqrt(EI / rho_A)  # rad/s, L = 1 m
    >>> target = pp.FitTarget(omega_truth_rad_s=w, tip_force_N=[0.0, 0.0, -1.0])
    >>> target.omega_truth_rad_s.round(2)
    array([ 51.87, 325.05])
    """

    omega_truth_rad_s: np.ndarray
    tip_force_N: np.ndarray
    tip_position_m: np.ndarray | None = None
    tip_displacement_m: np.ndarray | None = None
    mac: np.ndarray | None = None
    source: str = ""
    extra_loads: tuple[LoadCase, ...] = ()
    labels: tuple[str, ...] | None = None
    truth_request: TruthRequest | None = None
    static_theory_gap_pct: float | None = None
    all_omega_rad_s: np.ndarray | None = None
    all_labels: tuple[str, ...] | None = None
    point_gains: tuple[tuple[str, np.ndarray], ...] | None = None
    tip_moment_Nm: np.ndarray | None = None
    load_point: str = "tip"
    tip_twist_rad: float | None = None
    mode_shapes: ModeShapes | None = None
    gravity_m_s2: np.ndarray | None = None

    def __post_init__(self) -> None:
        """Check the frequencies, load cases and labels; freeze the arrays.

        Every vector holds finite real numbers of its size (a NaN tip, a complex frequency or
        a string is refused naming the field: :func:`prbdm_pin.validate.real_vector`).
        """
        w = real_vector("omega_truth_rad_s", self.omega_truth_rad_s, "rad/s")
        if w.size == 0 or np.any(w <= 0):
            raise BeamInputError(f"omega_truth_rad_s = {w.tolist()}: must be finite and > 0")
        if np.any(np.diff(w) < 0):
            raise BeamInputError(f"omega_truth_rad_s = {w.tolist()}: must be ascending")
        object.__setattr__(self, "omega_truth_rad_s", w)
        object.__setattr__(self, "tip_force_N", real_vector("tip_force_N", self.tip_force_N,
                                                            "N", 3))
        for name in ("tip_position_m", "tip_displacement_m"):
            v = getattr(self, name)
            if v is not None:
                object.__setattr__(self, name, real_vector(name, v, "m", 3))
        if self.mac is not None:
            object.__setattr__(self, "mac", real_vector("mac", self.mac, "1"))
        if isinstance(self.extra_loads, (str, bytes, dict, LoadCase)) or not hasattr(
                self.extra_loads, "__iter__"):
            raise InputTypeError(f"extra_loads = {shown(self.extra_loads)}: must be a tuple of "
                                 "prbdm_pin.LoadCase (or give fit(..., extra_loads=...) "
                                 "multiples of the tip force)")
        extra = tuple(self.extra_loads)
        if extra and not self.has_static:
            raise BeamInputError("extra_loads: need the primary load case's truth tip position "
                                 "and displacement too")
        for i, c in enumerate(extra):
            check_type(f"extra_loads[{i}]", c, LoadCase)
        object.__setattr__(self, "extra_loads", extra)
        if self.labels is not None:
            labels = tuple(str(v) for v in self.labels)
            if len(labels) != w.size:
                raise BeamInputError(f"labels has {len(labels)} entries: one per truth "
                                     f"frequency ({w.size}) needed")
            object.__setattr__(self, "labels", labels)
        if (self.all_omega_rad_s is None) != (self.all_labels is None):
            raise BeamInputError("all_omega_rad_s, all_labels: give both (every truth mode and "
                                 "its label) or neither")
        if self.point_gains is not None:
            if self.all_omega_rad_s is None:
                raise BeamInputError("point_gains: need all_omega_rad_s (the modes they are of)")
            gains = tuple((str(name), real_vector(f"point_gains[{name!r}]", g, "1/sqrt(kg)",
                                                  len(self.all_omega_rad_s)))
                          for name, g in self.point_gains)
            object.__setattr__(self, "point_gains", gains)
        if self.all_omega_rad_s is not None:
            wa = real_vector("all_omega_rad_s", self.all_omega_rad_s, "rad/s")
            la = tuple(str(v) for v in self.all_labels)
            if len(la) != wa.size:
                raise BeamInputError(f"all_labels has {len(la)} entries: one per mode of "
                                     f"all_omega_rad_s ({wa.size}) needed")
            object.__setattr__(self, "all_omega_rad_s", wa)
            object.__setattr__(self, "all_labels", la)
        if self.mode_shapes is not None:
            check_type("mode_shapes", self.mode_shapes, ModeShapes)
            if self.all_omega_rad_s is None or \
                    self.mode_shapes.deflection.shape[0] != self.all_omega_rad_s.size:
                raise BeamInputError("mode_shapes: one row per mode of all_omega_rad_s needed")
        self._check_load()

    def _check_load(self) -> None:
        """Check the spatial load case's moment, point and twist (each names its field)."""
        from ..truth.corner_static import POINT_SIDES

        if self.tip_moment_Nm is not None:
            object.__setattr__(self, "tip_moment_Nm",
                               real_vector("tip_moment_Nm", self.tip_moment_Nm, "N m", 3))
        if not isinstance(self.load_point, str) or self.load_point not in POINT_SIDES:
            raise BeamInputError(f"load_point = {shown(self.load_point)}: must be one of "
                                 f"{', '.join(POINT_SIDES)}")
        if self.tip_twist_rad is not None:
            object.__setattr__(self, "tip_twist_rad",
                               check_float("tip_twist_rad", self.tip_twist_rad, unit="rad"))
        if self.gravity_m_s2 is not None:
            from ..truth.self_weight import check_gravity

            object.__setattr__(self, "gravity_m_s2",
                               read_only(check_gravity(self.gravity_m_s2)))

    @property
    def has_static(self) -> bool:
        """Whether a truth tip position (and displacement) is available."""
        return self.tip_position_m is not None and self.tip_displacement_m is not None

    @property
    def load_cases(self) -> tuple[LoadCase, ...]:
        """Every static load case, the primary one (``tip_force_N``) first; () without one."""
        if not self.has_static:
            return ()
        return (LoadCase(self.tip_force_N, self.tip_position_m, self.tip_displacement_m),
                *self.extra_loads)

    def first(self, n_freq: int) -> FitTarget:
        """Return the same target keeping only the first ``n_freq`` frequencies."""
        if not 1 <= n_freq <= self.omega_truth_rad_s.size:
            raise BeamInputError(
                f"frequencies = {n_freq}: must be in 1..{self.omega_truth_rad_s.size} "
                "(truth frequencies available)"
            )
        mac = None if self.mac is None else self.mac[:n_freq]
        labels = None if self.labels is None else self.labels[:n_freq]
        return replace(self, omega_truth_rad_s=self.omega_truth_rad_s[:n_freq], mac=mac,
                       labels=labels)

    def shape_notes(self) -> list[str]:
        """List why a chain may miss this target, one line per truth mode that is not beam-like.

        A mode is not beam-like when labelled other than bending, or when its MAC with a beam
        bending mode is below 0.8.
        """
        out = []
        for k in range(self.omega_truth_rad_s.size):
            label = None if self.labels is None else self.labels[k]
            mac = None if self.mac is None else float(self.mac[k])
            if (label is not None and label != "bending") or (mac is not None and mac < 0.8):
                what = f"{label}, " if label is not None else ""
                out.append(f"truth mode {k + 1} ({self.omega_truth_rad_s[k]:.6g} rad/s; {what}"
                           f"MAC {mac:.2f} with a beam bending mode) is not beam-like: a chain "
                           "of rigid links has no mode of its shape")
        return out


def target_from_truth(truth, tip_force_N: np.ndarray,
                      request: TruthRequest | None = None) -> FitTarget:
    """Build a :class:`FitTarget` from a truth result.

    Parameters
    ----------
    truth : TruthResult
        The truth computation (frequencies in rad/s, tip position and displacement in m).
    tip_force_N : ndarray, shape (3,)
        The tip force the truth's statics were computed under, N.
    request : TruthRequest or None
        The ``compute_truth`` request that produced ``truth``, recorded in the target (default:
        the truth's own record, ``truth.request``, set by :func:`prbdm_pin.compute_truth`), and
        from there in the fit and its ``fit.json``.

    Returns
    -------
    FitTarget
        The target, with the truth's frequencies, tip, MAC and mode labels.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01,
    ...                tip_force_N=[0.0, 0.0, -100.0])
    >>> truth = pp.compute_truth(beam, model="beam", modes=2)
    >>> target = pp.target_from_truth(truth, beam.tip_force_N)
    >>> target.omega_truth_rad_s.round(2)
    array([ 51.87, 325.05])
    >>> EI = beam.material.E_Pa * 0.05 * 0.01**3 / 12  # N m^2
    >>> (np.array([1.8751041, 4.6940911])**2 * np.sqrt(EI / 3.925)).round(2)  # Euler-Bernoulli
    array([ 51.87, 325.05])
    """
    from ..truth.result import TruthResult

    check_type("truth", truth, TruthResult, "a prbdm_pin.TruthResult (compute_truth)")
    if request is None:
        request = truth.request
    mac = getattr(truth, "mac_beam", None)
    src = f"{truth.model}, mesh level {truth.mesh_level}, selection {truth.selection}"
    labels = tuple(truth.labels[int(i)] for i in truth.mode_index)
    return FitTarget(
        omega_truth_rad_s=truth.omega_rad_s,
        tip_force_N=tip_force_N,
        tip_position_m=truth.tip_position_m,
        tip_displacement_m=truth.tip_displacement_m,
        mac=mac,
        source=src,
        labels=labels,
        truth_request=request,
        static_theory_gap_pct=getattr(truth, "static_theory_gap_pct", None),
        all_omega_rad_s=truth.modal.omega_rad_s,
        all_labels=tuple(truth.labels),
        mode_shapes=truth_mode_shapes(truth.modal),
    )


def model_target(model, tip_forces_N) -> FitTarget:
    """Take a PRBDM as its own truth.

    The target holds the model's frequencies (rad/s) and its large-deflection tip (m) under
    each force of ``tip_forces_N`` (k, 3), N; the first is the primary load case, the others
    ``extra_loads``. A fit to it should recover the model (identifiability checks).
    """
    forces = np.asarray(tip_forces_N, dtype=float).reshape(-1, 3)
    rest = model.tip_position()
    cases = []
    for F in forces:
        tip = model.static_deflection(F)[1]
        cases.append(LoadCase(F, tip, tip - rest))
    first = cases[0]
    return FitTarget(model.natural_frequencies(), first.tip_force_N, first.tip_position_m,
                     first.tip_displacement_m, extra_loads=tuple(cases[1:]),
                     source=f"a {model.n_joints}R PRBDM")

