"""The spatial fit's deflection term: the tip in 3D and its twist under a tip load.

The load case is the target's: a dead force ``tip_force_N`` (N) at ``load_point`` (the tip
centre or a tip corner) and a dead moment ``tip_moment_Nm`` (N m), world axes; its truth is the
tip centre's position ``tip_position_m`` (m) and the tip twist ``tip_twist_rad`` (rad): the
angle of the tip's corner-to-corner line to the world y axis in the y-z plane, as
:mod:`prbdm_pin.truth.corner_static` reports it. The chain is solved under the same load
(:meth:`~prbdm_pin.model.prbdm_model.PrbdmModel.static_deflection`, large deflection) and
compared as Eq. 19 compares the planar tip:

    e_p = ||p_model - p_truth|| / s_p,    e_t = |phi_model - phi_truth| / s_t,

s_p the truth tip position's length (``deflection_norm="position"``, Eq. 19) or its
displacement's, s_t the truth twist's magnitude (when the truth does not twist, the twist that
moves a corner by the truth tip displacement, ||d_truth|| / w(L)). The deflection loss is their
rms, 100 sqrt((e_p^2 + e_t^2) / 2) %; the combined loss Eq. 27's hypot of the eigen loss and
it. The term's residual is the signed error vector scaled so that its squared norm is the
deflection loss squared, times the number of selected modes in a combined fit: the sum of
squares the least-squares fit minimises is then N (eigen^2 + deflection^2), Eq. 27 squared.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..errors import BeamInputError, SolveError
from ..options.objects import FitOptions
from .objectives import tip_scale_m
from .target import FitTarget

__all__ = ["DeflectionTerm", "chain_twist_rad", "spatial_load_target", "spatial_model_target",
           "spatial_losses"]

# the truth label of each joint axis's modes, for a chain taken as its own truth
_KIND = {"y": "bending", "x": "torsion", "z": "in-plane"}


def chain_twist_rad(model, q: np.ndarray) -> float:
    """Return the chain's tip twist at pose ``q`` (rad): the corner line's angle to y in y-z."""
    left = model.point_kinematics("tip_corner_left", q)[0]
    right = model.point_kinematics("tip_corner_right", q)[0]
    d = left - right
    return math.atan2(float(d[2]), float(d[1]))


class DeflectionTerm:
    """The tip's and the twist's errors under the target's load case (module notes)."""

    label = "deflection"
    size = 4

    def __init__(self, target: FitTarget, options: FitOptions, weight: float = 1.0):
        missing = [n for n in ("tip_position_m", "tip_displacement_m", "tip_twist_rad")
                   if getattr(target, n) is None]
        if missing:
            raise BeamInputError(
                f"{', '.join(missing)}: a spatial {options.objective.value} fit (axes = "
                f"{options.axes.value!r}) matches the truth's tip in 3D and its twist under the "
                "tip load; give a target with both (spatial_load_target with a corner_static "
                "solution, or spatial_model_target)")
        if target.extra_loads:
            raise BeamInputError("extra_loads: a spatial deflection fit takes one load case "
                                 "(tip_force_N at load_point, tip_moment_Nm)")
        if not np.linalg.norm(target.tip_displacement_m) > 0.0:
            raise BeamInputError("tip_displacement_m = 0: a spatial deflection fit needs a "
                                 "deflection")
        self.t, self.weight = target, float(weight)
        self._q = None  # the last equilibrium: the next design's solve starts from it
        self.scale_m = tip_scale_m(target.tip_position_m, target.tip_displacement_m,
                                   options.deflection_norm)

    def twist_scale_rad(self, model) -> float:
        """Return what a twist error is divided by, rad (module notes)."""
        if self.t.tip_twist_rad != 0.0:
            return abs(self.t.tip_twist_rad)
        return float(np.linalg.norm(self.t.tip_displacement_m)) / float(
            model.beam.half_width_m[-1])

    def tip(self, model) -> tuple[np.ndarray, float]:
        """Return the chain's tip position (m, (3,)) and twist (rad) under the load case."""
        t = self.t
        q0 = self._q if self._q is not None and self._q.size == model.n_springs else None
        try:
            q, p = model.static_deflection(t.tip_force_N, q0=q0, tip_moment_Nm=t.tip_moment_Nm,
                                           point=t.load_point)
        except SolveError:
            if q0 is None:
                raise
            # a start far from this design's equilibrium: solve from the straight pose
            q, p = model.static_deflection(t.tip_force_N, tip_moment_Nm=t.tip_moment_Nm,
                                           point=t.load_point)
        self._q = q
        return p, chain_twist_rad(model, q)

    def errors(self, model) -> np.ndarray:
        """Return (p_model - p_truth) / s_p (3,) and the twist's (phi_m - phi_t) / s_t."""
        p, phi = self.tip(model)
        return np.r_[(p - self.t.tip_position_m) / self.scale_m,
                     (phi - self.t.tip_twist_rad) / self.twist_scale_rad(model)]

    def residual(self, design, model) -> np.ndarray:
        """Return the weighted errors (dimensionless): norm = weight x deflection loss / 100."""
        return self.errors(model) * (self.weight / math.sqrt(2.0))

    def loss_pct(self, model) -> float:
        """Return the deflection loss 100 sqrt((e_p^2 + e_t^2) / 2), %."""
        return 100.0 * float(np.linalg.norm(self.errors(model))) / math.sqrt(2.0)


def deflection_terms(sel, target: FitTarget, options: FitOptions) -> tuple:
    """Return the deflection term a spatial fit's objective asks for (none for ``eigen``).

    In a combined fit its weight is sqrt(N), N the selected modes (module notes).
    """
    if not options.objective.has_deflection_term:
        return ()
    w = math.sqrt(sel.omega_truth_rad_s.size) if options.objective.has_eigen_term else 1.0
    return (DeflectionTerm(target, options, w),)


def spatial_losses(d, model) -> dict:
    """Return the FitResult fields of a spatial fit's losses and tip at ``model``.

    ``objective``, ``eigen_loss_pct`` (the rms of the selected modes' relative errors, %),
    ``deflection_loss_pct`` and ``combined_loss_pct`` (%, NaN without a deflection term) and
    ``tip_position_model_m`` ((1, 3), m, or None).
    """
    r = d.frequencies(model) / d.sel.omega_truth_rad_s - 1.0
    eig = 100.0 * float(np.sqrt(np.mean(r * r)))
    term = next((t for t in d.terms if isinstance(t, DeflectionTerm)), None)
    if term is None:
        return {"objective": "eigen", "eigen_loss_pct": eig, "deflection_loss_pct": math.nan,
                "combined_loss_pct": math.nan, "tip_position_model_m": None}
    defl = term.loss_pct(model)
    return {"objective": d.o.objective.value, "eigen_loss_pct": eig,
            "deflection_loss_pct": defl, "combined_loss_pct": math.hypot(eig, defl),
            "tip_position_model_m": term.tip(model)[0][None, :]}


def spatial_load_target(target: FitTarget, solution) -> FitTarget:
    """Return ``target`` with the load case of a 3D static truth.

    Parameters
    ----------
    target : FitTarget
        The modal target (e.g. :func:`~prbdm_pin.fitting.target.target_from_truth`).
    solution : CornerSolution
        :func:`prbdm_pin.truth.corner_static.corner_static`'s: its force (N), point, moment
        (N m), tip position and displacement (m) and twist (rad) replace the target's load case.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 0.3], half_width_m=[0.05, 0.05], thickness_m=0.002,
    ...                tip_force_N=[0.0, 0.0, -1.0])
    >>> target = pp.FitTarget(omega_truth_rad_s=[117.2, 732.6], tip_force_N=beam.tip_force_N)
    >>> corner = pp.corner_static(beam, "plate", point="tip_corner_left", level=0)
    >>> loaded = pp.spatial_load_target(target, corner)
    >>> loaded.load_point, bool(loaded.tip_twist_rad != 0.0)  # a corner force twists the tip
    ('tip_corner_left', True)
    """
    from ..options.validate import check_type
    from ..truth.corner_static import CornerSolution

    check_type("target", target, FitTarget)
    check_type("solution", solution, CornerSolution, "a CornerSolution (corner_static)")
    return replace(target, tip_force_N=solution.tip_force_N,
                   tip_position_m=solution.tip_position_m,
                   tip_displacement_m=solution.tip_displacement_m,
                   tip_moment_Nm=solution.tip_moment_Nm, load_point=solution.point,
                   tip_twist_rad=solution.tip_twist_rad, extra_loads=())


def spatial_model_target(model, tip_force_N: np.ndarray, tip_moment_Nm: np.ndarray | None = None,
                         point: str = "tip") -> FitTarget:
    """Take a spatial PRBDM as its own truth: its modes by kind and its tip under one load.

    Parameters
    ----------
    model : PrbdmModel
        A spatial chain with a beam (its corners need the width).
    tip_force_N : array_like, shape (3,)
        The force at ``point``, N, world axes.
    tip_moment_Nm : array_like, shape (3,), optional
        A tip moment, N m, world axes.
    point : str
        ``tip``, ``tip_corner_left`` or ``tip_corner_right``.

    Returns
    -------
    FitTarget
        Every mode of the chain (rad/s, each axis block's at the straight pose, labelled
        ``bending`` (y), ``torsion`` (x) or ``in-plane`` (z)), and the large-deflection tip
        position (m) and twist (rad) under the load.
    """
    import scipy.linalg

    M, k = model.mass_matrix(), model.stiffness_Nm_per_rad
    w, labels = [], []
    for a in model.axes.joint_order:
        idx = model.axis_index(a)
        lam = scipy.linalg.eigh(np.diag(k[idx]), M[np.ix_(idx, idx)], eigvals_only=True)
        w += list(np.sqrt(lam))
        labels += [_KIND[a]] * idx.size
    order = np.argsort(w, kind="stable")
    w_all = np.asarray(w)[order]
    q, p = model.static_deflection(tip_force_N, tip_moment_Nm=tip_moment_Nm, point=point)
    first = [i for i in order if labels[i] == "bending"]
    return FitTarget(
        omega_truth_rad_s=np.sort(np.asarray(w)[first]), tip_force_N=tip_force_N,
        tip_position_m=p, tip_displacement_m=p - model.tip_position(),
        source=f"a {model.n_joints}R {model.axes.value} PRBDM",
        all_omega_rad_s=w_all, all_labels=tuple(labels[i] for i in order),
        tip_moment_Nm=tip_moment_Nm, load_point=point, tip_twist_rad=chain_twist_rad(model, q))
