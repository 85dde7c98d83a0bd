"""A fit in gravity: the planar ``joint`` chain evaluated in the truth's gravity.

``fit(beam, gravity_target(beam, g), n, stiffness="joint")`` comes here (the command line's
``prbdm fit ... --truth-model beam --stiffness joint --gravity GX,0,GZ``). The chain is judged as
the truth is: its frequencies about its own sag in g (:mod:`prbdm_pin.fitting.gravity_chain`),
its tip under each load case plus its weight.

Two stages. The multistart of the fit without gravity (eigen objective, the same frequencies)
gives the start; a local least-squares over x = [u, ln s] (stick-breaking lengths, joint spring
factors, as :class:`~prbdm_pin.fitting.joint.JointResiduals`) then solves the residuals in
gravity, with a finite-difference Jacobian (every evaluation is a damped Newton equilibrium
and a dense eigensolve, a few milliseconds). Scope: the planar chain (axes y), one factor per
joint, the straight-pose comparison (no sweep, no ``unique`` rule, no warm start).
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
from scipy.optimize import least_squares

from ..errors import BeamInputError, SolveError
from ..options.choices import Objective, StiffnessKind, UniqueRule
from ..options.objects import FitOptions
from .gravity_chain import chain_in_gravity
from .mode_records import mode_records
from .objectives import (
    eigen_errors,
    eigen_residuals,
    eigen_weights,
    mode_errors_pct,
    tip_displacement_errors,
    tip_position_errors,
    worst_mode_error_pct,
)
from .problem import lengths_from_unit, make_problem, unit_from_lengths
from .results import FitResult
from .spec import tip_scales_m
from .target import FitTarget

__all__ = ["fit_in_gravity"]


def _refuse(o: FitOptions, start, extra_loads) -> None:
    for name, bad, what in (
            ("axes", o.axes.spatial, f"{o.axes.value!r}: the planar chain (axes 'y') only"),
            ("stiffness", o.stiffness is not StiffnessKind.JOINT,
             f"{o.stiffness.value!r}: one factor per joint ('joint') only"),
            ("joint_sweep", o.joint_sweep, "the straight pose only"),
            ("unique", o.unique is not UniqueRule.NONE, "no unique rule"),
            ("start", start is not None, "no warm start"),
            ("extra_loads", bool(extra_loads), "the primary load case only")):
        if bad:
            raise BeamInputError(f"{name} = {what}: a fit in gravity (target.gravity_m_s2) "
                                 "takes this")


class _Residuals:
    """Residuals of a design in gravity over x = [u (n), ln s (n)]."""

    def __init__(self, problem, objective: Objective):
        self.p = problem
        t = problem.target
        self.g = t.gravity_m_s2
        self.eigen = objective.has_eigen_term
        self.cases = t.load_cases if objective.has_deflection_term else ()
        self.scale = tip_scales_m(problem) if self.cases else np.zeros(0)
        self.d = eigen_weights(t.omega_truth_rad_s, problem.squared, problem.eigen_norm)
        self.nfev = 0

    def design(self, x):
        n = self.p.n_joints
        lengths = lengths_from_unit(x[:n], self.p.length_m, self.p.min_fraction)
        return lengths, np.exp(x[n:])

    def evaluate(self, x):
        lengths, s = self.design(x)
        model, K0 = self.p.parametrisation.build(self.p, lengths)
        return chain_in_gravity(model.with_stiffness(s * K0), self.g,
                                [c.tip_force_N for c in self.cases])

    def __call__(self, x):
        self.nfev += 1
        size = (self.p.n_freq if self.eigen else 0) + 3 * len(self.cases)
        try:
            ev = self.evaluate(x)
        except (SolveError, BeamInputError, np.linalg.LinAlgError):
            return np.full(size, 1e3)  # a buckled or unsolvable design: far from any match
        out = []
        if self.eigen:
            out.append(eigen_residuals(ev.omega_rad_s[None, : self.p.n_freq],
                                       self.p.target.omega_truth_rad_s, self.p.squared,
                                       weights=self.d).ravel())
        wc = 1.0 / math.sqrt(max(len(self.cases), 1))
        for tip, c, sc in zip(ev.tip_positions_m, self.cases, self.scale, strict=True):
            out.append((tip - c.tip_position_m) * wc / sc)
        return np.concatenate(out)


def fit_in_gravity(beam, target: FitTarget, joints: int, o: FitOptions, *, workers: int = 1,
                   progress: bool = True, start=None, extra_loads=()) -> FitResult:
    """Fit the planar ``joint`` chain to a target in gravity (see the module notes).

    Parameters as :func:`prbdm_pin.fitting.multistart.fit`, ``target.gravity_m_s2`` set and
    ``o`` resolved.

    Returns
    -------
    FitResult
        ``gravity_m_s2`` set; frequencies (rad/s) about the chain's sag, tips (m) under the
        load plus the weight, losses (%) in gravity.
    """
    from .multistart import fit

    t0 = time.perf_counter()
    _refuse(o, start, extra_loads)
    objective = o.objective
    if objective.has_deflection_term and not target.has_static:
        raise BeamInputError(f"objective = {objective.value!r}: the target in gravity has no "
                             "tip deflection (a weight along the member and no tip force)")
    # stage 1: the multistart without gravity on the same frequencies
    free = dataclasses.replace(target, gravity_m_s2=None, tip_position_m=None,
                               tip_displacement_m=None, extra_loads=())
    base = fit(beam, free, joints, o.replace(objective="eigen"), workers=workers,
               progress=progress)
    problem = make_problem(beam, target, joints, o)
    res = _Residuals(problem, objective)
    n = problem.n_joints
    x0 = np.concatenate([unit_from_lengths(base.lengths_m, beam.length_m, problem.min_fraction),
                         np.log(base.factors)])
    # stage 2: the residuals in gravity; tolerances at the fit's own (exact match) level, and
    # the budget of max_nfev Jacobians (each 2n + 1 evaluations by forward differences)
    sol = least_squares(res, x0, bounds=(np.r_[np.zeros(n), np.full(n, -np.inf)],
                                         np.r_[np.ones(n), np.full(n, np.inf)]),
                        method="trf", xtol=1e-12, ftol=1e-14, gtol=1e-14,
                        max_nfev=o.max_nfev * (2 * n + 1))
    lengths, s = res.design(sol.x)
    return _result(problem, base, res, lengths, s, sol, t0)


def _result(problem, base: FitResult, res: _Residuals, lengths, s, sol, t0) -> FitResult:
    """Package the design in gravity: ``base``'s record with every number of the chain in g."""
    from .result import _bound_notes

    t = problem.target
    model, K0 = problem.parametrisation.build(problem, lengths)
    K = s * K0
    ev = chain_in_gravity(model.with_stiffness(K), t.gravity_m_s2,
                          [c.tip_force_N for c in t.load_cases])
    w = ev.omega_rad_s[None, : problem.n_freq]
    err = eigen_errors(w, t.omega_truth_rad_s, problem.squared, problem.eigen_norm)
    eig_pct = float(100.0 * np.mean(err))
    pos = disp = math.nan
    if t.has_static:
        c = t.load_cases[0]
        pos = float(100.0 * tip_position_errors(ev.tip_positions_m[:1], c.tip_position_m)[0])
        disp = float(100.0 * tip_displacement_errors(ev.tip_positions_m[:1], c.tip_position_m,
                                                     c.tip_displacement_m)[0])
    tip_pct = pos if problem.deflection_norm.value == "position" else disp
    omega_errors = mode_errors_pct(w, t.omega_truth_rad_s)
    worst = worst_mode_error_pct(omega_errors)
    notes = t.shape_notes() + _bound_notes(lengths, problem.length_m, problem.min_fraction)
    return dataclasses.replace(
        base, objective=problem.options.objective.value, lengths_m=lengths,
        stiffness_Nm_per_rad=K, stiffness_per_pose_Nm_per_rad=K[None], factors=s,
        omega_truth_rad_s=t.omega_truth_rad_s, omega_model_rad_s=w,
        eigen_errors_pct=100.0 * err, eigen_loss_pct=eig_pct, deflection_loss_pct=pos,
        displacement_loss_pct=disp,
        combined_loss_pct=float(math.hypot(eig_pct, tip_pct)),
        tip_position_model_m=ev.tip_positions_m[:1] if t.has_static else None,
        tip_position_truth_m=t.tip_position_m, tip_displacement_truth_m=t.tip_displacement_m,
        tip_force_N=t.tip_force_N, truth_source=t.source, truth_request=None,
        nfev=base.nfev + res.nfev, wall_time_s=time.perf_counter() - t0,
        success=bool(sol.success),
        message=f"{base.message}; in gravity: {sol.message}", warnings=tuple(notes),
        omega_errors_pct=omega_errors, worst_mode_error_pct=worst,
        omega_export_rad_s=w[0], omega_export_errors_pct=omega_errors[0],
        worst_export_error_pct=worst, options=problem.options,
        stiffness_pose="joint: pose-independent springs, fitted about the sag in gravity",
        modes=mode_records(t.labels, t.omega_truth_rad_s, w[0]), gravity_m_s2=t.gravity_m_s2)
