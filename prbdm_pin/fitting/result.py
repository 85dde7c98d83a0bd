"""A chosen design evaluated in full through the Pinocchio model and packaged as a FitResult.

The result carries the notes a user needs (modes a chain cannot follow, an exported model that
misses, links on their length bound).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..errors import SolveError
from ..options.checks import check_choice
from ..options.choices import Objective
from .evaluate import evaluate
from .mode_records import mode_records
from .objectives import mode_errors_pct, worst_mode_error_pct
from .planar_gains import planar_gain_records
from .problem import FitProblem
from .results import FitResult

__all__ = ["EXACT_MATCH_PCT", "EXPORT_WARN_PCT", "BOUND_TOL", "ExportedSprings",
           "result_from_design"]

# eigen loss (%) above which a joint fit of n frequencies at the straight pose has not matched
# them (reached fits end at 1e-11 % or below)
EXACT_MATCH_PCT = 1e-4
# worst per-mode error (%) of the exported model at the straight pose above which a fit warns
EXPORT_WARN_PCT = 1.0
# a link within this fraction of L of its lower bound is reported as sitting on it
BOUND_TOL = 1e-6


class ExportedSprings(NamedTuple):
    """What a fitted design exports, as its parametrisation says (``Parametrisation.export``).

    Attributes
    ----------
    springs_Nm_per_rad : ndarray, shape (n,)
        The exported joint springs, N m/rad.
    pose_rad : ndarray, shape (n,)
        The pose they were fitted at, rad.
    scf_mean : float
        The mean stiffness factor (Eq. 25 for the SCFs), dimensionless.
    scf_deviation_pct : ndarray, shape (m,)
        Each pose's SCF deviation from the mean (Eq. 26; zeros for one factor per joint), %.
    described : str
        What the exported springs are, in words.
    """

    springs_Nm_per_rad: np.ndarray
    pose_rad: np.ndarray
    scf_mean: float
    scf_deviation_pct: np.ndarray
    described: str


def result_from_design(problem: FitProblem, lengths_m, factors, *, objective: Objective,
                       seed: int,
                       starts: int, starts_run: int, nfev: int, start_losses_pct,
                       wall_time_s: float, success: bool, message: str) -> FitResult:
    """Evaluate a design in full (frequencies, tip under load) and package it as a FitResult.

    Parameters
    ----------
    problem : FitProblem
        The fit problem the design solves; its options are recorded in the result.
    lengths_m : array_like, shape (n+1,)
        Link lengths, m.
    factors : array_like
        Spring factors (dimensionless): the ``joint`` factors on the finite-segment springs,
        shape (n,), or the ``paper`` SCFs, one per pose.
    objective : Objective or str
        The objective the design was fitted to.
    seed : int
        The seed of the starts.
    starts, starts_run : int
        The starts asked for and the starts run.
    nfev : int
        Model evaluations of the whole fit.
    start_losses_pct : array_like
        Each start's loss, %.
    wall_time_s : float
        The fit's wall time, s.
    success : bool
        The chosen start's solver success flag.
    message : str
        The fit's message (a failed static deflection is appended to it).

    Returns
    -------
    FitResult
        The design with its model's frequencies (rad/s), tip (m), springs (N m/rad), per-mode
        errors (%) and notes.
    """
    objective = check_choice("objective", objective, Objective)
    t = problem.target
    try:
        ev = evaluate(problem, lengths_m, factors, deflection=t.has_static)
    except SolveError as exc:
        ev = evaluate(problem, lengths_m, factors, deflection=False)
        message = f"{message}; static deflection failed: {exc}"
    P = problem.parametrisation
    model, K0 = P.build(problem, lengths_m)
    extra = bool(t.extra_loads) and ev.extra_tip_position_m is not None
    notes = P.fit_notes(problem, objective, ev.eigen_loss_pct, starts_run) + t.shape_notes()
    n = problem.n_joints
    exported = P.export(problem, ev, K0)
    K, described = exported.springs_Nm_per_rad, exported.described
    omega_errors = mode_errors_pct(ev.omega_model_rad_s, t.omega_truth_rad_s)
    # the exported model on its own: its frequencies at the straight pose
    w_export = model.with_stiffness(K).natural_frequencies(np.zeros(n))[: problem.n_freq]
    export_errors = mode_errors_pct(w_export, t.omega_truth_rad_s)[0]
    worst_export = worst_mode_error_pct(export_errors)
    if worst_export > EXPORT_WARN_PCT:
        k = int(np.argmax(np.abs(export_errors)))
        notes.append(f"the exported model ({described}) misses "
                     f"truth mode {k + 1} by {export_errors[k]:+.3g} % at the straight pose "
                     f"(every mode: {_pct_list(export_errors)}); the {problem.eigen_norm}-norm "
                     f"eigen loss of {ev.eigen_loss_pct:.3g} % does not show it"
                     + P.export_advice)
    notes.extend(_bound_notes(ev.lengths_m, problem.length_m, problem.min_fraction))
    gains = planar_gain_records(problem, ev.lengths_m, K)
    worst = max(gains, key=lambda g: abs(g["error_pct"]), default=None)
    if worst is not None and abs(worst["error_pct"]) > EXPORT_WARN_PCT:
        notes.append(f"modal gains: worst {worst['error_pct']:+.3g} % (mode at "
                     f"{worst['omega_truth_rad_s']:.6g} rad/s, {worst['point']})")
    return FitResult(
        beam_name=problem.beam.name, beam_fingerprint=problem.beam.fingerprint(),
        joints=problem.n_joints, frequencies=problem.n_freq, objective=objective.value,
        stiffness=P.name, lengths_m=ev.lengths_m, stiffness_Nm_per_rad=K,
        stiffness_per_pose_Nm_per_rad=ev.stiffness_Nm_per_rad, factors=ev.factors,
        scf_mean=exported.scf_mean, scf_deviation_pct=exported.scf_deviation_pct,
        poses_rad=problem.poses_rad,
        omega_truth_rad_s=t.omega_truth_rad_s, omega_model_rad_s=ev.omega_model_rad_s,
        eigen_errors_pct=100.0 * ev.eigen_errors, eigen_loss_pct=ev.eigen_loss_pct,
        deflection_loss_pct=ev.deflection_loss_pct,
        displacement_loss_pct=ev.displacement_loss_pct,
        combined_loss_pct=float(math.hypot(ev.eigen_loss_pct,
                                           ev.tip_loss_pct(problem.deflection_norm))),
        tip_position_model_m=ev.tip_position_m, tip_position_truth_m=t.tip_position_m,
        tip_displacement_truth_m=t.tip_displacement_m, tip_force_N=t.tip_force_N, mac=t.mac,
        truth_source=t.source, truth_request=t.truth_request,
        static_theory_gap_pct=math.nan if t.static_theory_gap_pct is None
        else float(t.static_theory_gap_pct),
        squared=problem.squared,
        xi=problem.options.xi_rad, eps=problem.options.eps_rad,
        seed=seed, starts=starts, starts_run=starts_run, nfev=nfev,
        start_losses_pct=start_losses_pct, wall_time_s=wall_time_s, success=success,
        message=message,
        extra_tip_force_N=np.array([c.tip_force_N for c in t.extra_loads]) if extra else None,
        extra_tip_position_truth_m=np.array([c.tip_position_m for c in t.extra_loads])
        if extra else None,
        extra_tip_position_model_m=ev.extra_tip_position_m if extra else None,
        warnings=tuple(notes),
        eigen_norm=problem.eigen_norm.value, min_fraction=problem.min_fraction,
        omega_errors_pct=omega_errors,
        worst_mode_error_pct=worst_mode_error_pct(omega_errors), export_pose_rad=exported.pose_rad,
        stiffness_pose=described, omega_export_rad_s=w_export,
        omega_export_errors_pct=export_errors, worst_export_error_pct=worst_export,
        options=problem.options,
        modes=mode_records(t.labels, t.omega_truth_rad_s, w_export), gains=gains,
    )


def _pct_list(errors_pct) -> str:
    return ", ".join(f"{v:+.3g}" for v in np.ravel(errors_pct)) + " %"


def _bound_notes(lengths_m: np.ndarray, length_m: float, min_fraction: float) -> list[str]:
    """One note per link at its lower bound: ``L_j <= min_fraction L + 1e-6 L``."""
    a = min_fraction * length_m
    return [f"link {j} ({v:.6g} m) sits on its length bound min_fraction L = {a:.6g} m "
            f"(min_fraction {min_fraction:g}): the fit wanted it shorter, so the optimum is "
            "constrained; fewer joints or a lower min_fraction (--min-link) may fit better"
            for j, v in enumerate(np.asarray(lengths_m, dtype=float))
            if v <= a + BOUND_TOL * length_m]

