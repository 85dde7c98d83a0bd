"""The fit of a spatial chain: link lengths and the springs of every axis, to modes by kind.

A spatial chain (``axes`` ``xy``, ``yz`` or ``xyz``) has at each node a spring per axis: y
(out-of-plane bending), z (in-plane bending), x (torsion). The fit matches the first
``frequencies`` truth modes of each kind (default n of each): bending-type modes (labelled
``bending`` or ``mixed``) to the y coordinates, ``torsion`` modes to x and ``in-plane`` modes to
z. At the straight pose the chain's mass matrix has no coupling between the axes (the
planform is symmetric about x and the section about its mid-plane, so every product of inertia
that would couple them vanishes), so each kind's model frequencies are the eigenvalues of its
own block: modes are paired by kind and, within a kind, in order, never across kinds. A truth
mode in the band that no axis represents (``chordwise``, or a kind whose axis the chain lacks)
is named in the result (``FitResult.modes``) with no model frequency.

The design is [u (n), log s]: the stick-breaking lengths and the spring factors, one per spring
(``joint``) or one per axis on the paper's Eq. 14 (``paper``), within a factor 1e3 either way
(``fitting/spatial_design.py``). The residual is each matched mode's relative error; each start
runs ``least_squares`` (dogbox, as the planar joint fit; the analytic Jacobian of
:mod:`.spatial_jacobian` for ``joint``, forward differences for ``paper``).

Which solution: with 2n + n len(axes) - n unknowns beyond the frequencies, a fit of n modes per
kind has many exact solutions (the torsion springs of one panel have 2-12). The rule: among the
starts that match every mode (loss at most ``EXACT_MATCH_PCT``) the one whose springs are
nearest their finite-segment values (least rms of log s); when none does, the lowest loss.
"""

from __future__ import annotations

import math
import time

import numpy as np
from scipy.optimize import least_squares

from ..chain.layout import sample_lengths
from ..errors import SolveError
from ..member.geometry import Beam
from ..options.objects import FitOptions
from .mode_shapes import pair_modes, pairing_notes
from .problem import unit_from_lengths
from .result import EXACT_MATCH_PCT, EXPORT_WARN_PCT
from .results import FitResult
from .spatial_deflection import spatial_losses
from .spatial_design import LOG_FACTOR_BOUND, SpatialDesign, spatial_terms
from .spatial_gains import GainsTerm, gain_records
from .spatial_jacobian import spatial_jacobian
from .spatial_target import select_spatial, spatial_records

__all__ = ["fit_spatial", "spatial_result", "LOG_FACTOR_BOUND"]

def _loss_pct(r: np.ndarray) -> float:
    return 100.0 * float(np.sqrt(np.mean(r * r)))


def _starts(d: SpatialDesign, starts: int, seed: int) -> list[np.ndarray]:
    """Return the starts: equal links at the finite-segment springs, then random ones.

    The random starts are drawn as the planar joint fit draws them: lengths uniform on the
    bounded simplex, factors log-uniform within a factor 2 of 1.
    """
    L, n = d.beam.length_m, d.n
    eq = np.full(n + 1, L / (n + 1))
    out = [np.r_[unit_from_lengths(eq, L, d.o.min_fraction), np.zeros(d.n_factors)]]
    if starts > 1:
        rng = np.random.default_rng(seed)
        L0 = sample_lengths(rng, L, n + 1, starts - 1, min_fraction=d.o.min_fraction)
        F0 = rng.uniform(-math.log(2.0), math.log(2.0), (starts - 1, d.n_factors))
        out += [np.r_[unit_from_lengths(L0[i], L, d.o.min_fraction), F0[i]]
                for i in range(starts - 1)]
    return out


def fit_spatial(beam: Beam, target, joints: int, options: FitOptions, *,
                progress: bool = True) -> FitResult:
    """Fit a spatial chain's lengths and springs to the truth's modes of each kind.

    Parameters
    ----------
    beam : Beam
    target : FitTarget
        Made by :func:`~prbdm_pin.fitting.target.target_from_truth` (it carries every truth
        mode and its label, ``all_omega_rad_s`` and ``all_labels``).
    joints : int
        n, the number of joint nodes (each with ``len(options.axes)`` springs).
    options : FitOptions
        With ``axes`` spatial; ``stiffness`` ``"joint"`` (a factor per spring) or ``"paper"``
        (a factor per axis on Eq. 14); ``objective`` ``eigen``, ``deflection`` or ``combined``
        (the tip in 3D and its twist: :mod:`.spatial_deflection`);
        ``frequencies`` is the number of modes of each kind (default n), ``starts``, ``seed``,
        ``max_nfev`` (residual evaluations per start) and ``loss_tol_pct`` apply.
    progress : bool
        Show a tqdm bar over the starts.

    Returns
    -------
    FitResult
        With ``axes``, the springs of every axis (N m/rad, node-major) and ``modes``: every
        matched truth mode by kind, and the unrepresented modes of the band.

    Raises
    ------
    BeamInputError
        A target without labelled truth modes, or with fewer modes of a kind than asked.
    """
    t0 = time.perf_counter()
    sel = select_spatial(target, options.axes, joints, options.frequencies)
    d = SpatialDesign(beam, sel, joints, options, spatial_terms(sel, target, options))
    lo = np.r_[np.zeros(joints), np.full(d.n_factors, -LOG_FACTOR_BOUND)]
    hi = np.r_[np.ones(joints), np.full(d.n_factors, LOG_FACTOR_BOUND)]
    tasks = _starts(d, options.starts, options.seed)
    if progress:
        from ..io.progress import progress_bar

        tasks = progress_bar(iterable=tasks, desc=f"fit {joints}R {options.axes.value}",
                             unit="start", leave=False)
    runs: list[tuple[float, float, int, np.ndarray, bool, str]] = []
    jac = spatial_jacobian(d)
    for i, x0 in enumerate(tasks):
        try:
            # dogbox, as the planar joint fit at one pose: the box bounds bind on jagged panels
            sol = least_squares(d.residual, x0, jac=jac, bounds=(lo, hi), method="dogbox",
                                max_nfev=options.max_nfev, x_scale=1.0)
        except SolveError:
            continue  # a start whose design left the chain's valid range
        loss = _loss_pct(sol.fun)
        runs.append((loss, float(np.sqrt(np.mean(sol.x[joints:] ** 2))), i, sol.x,
                     bool(sol.success), str(sol.message)))
        if options.loss_tol_pct is not None and loss <= options.loss_tol_pct:
            break
    if not runs:
        raise SolveError(f"axes = {options.axes.value!r}: no start of the spatial fit "
                         "gave a valid chain")
    exact = [r for r in runs if r[0] <= EXACT_MATCH_PCT]
    best = min(exact, key=lambda r: (r[1], r[2])) if exact else min(runs, key=lambda r: r[:1])
    return spatial_result(beam, target, d, best, runs, time.perf_counter() - t0)


def spatial_result(beam, target, d: SpatialDesign, best, runs, wall_s: float,
                   message: str | None = None) -> FitResult:
    """Evaluate the chosen design in full and package it as a FitResult.

    ``best`` and ``runs`` are (loss %, rms log factor, index, x, success, message) tuples;
    ``message`` replaces the result's message (default: how the start was chosen).
    """
    loss, _, index, x, success, solver_message = best
    model = d.model(x)
    # the reported pairs are by kind and shape (MAC), not by the rank the fit matched
    w, mac, moved = pair_modes(d, model, target.mode_shapes)
    sel, o, n = d.sel, d.o, d.n
    nk = n * d.m
    errors = 100.0 * (w / sel.omega_truth_rad_s - 1.0)
    records = spatial_records(sel, w, target, mac)
    notes = pairing_notes(sel, w, moved, mac)
    k_worst = int(np.argmax(np.abs(errors)))
    if abs(errors[k_worst]) > EXPORT_WARN_PCT:
        notes.append(f"the fitted model misses truth mode {sel.index[k_worst] + 1} "
                     f"({sel.kind[k_worst]}, {sel.omega_truth_rad_s[k_worst]:.6g} rad/s) by "
                     f"{errors[k_worst]:+.3g} %")
    unrepresented = [r for r in records if r["omega_model_rad_s"] is None]
    if unrepresented:
        notes.append(f"{len(unrepresented)} truth mode(s) in the band are not matched (kinds: "
                     f"{', '.join(sorted({r['kind'] for r in unrepresented}))}): the chain has "
                     f"{n} modes about each of its axes and none of a kind without an axis; "
                     "they are named in modes")
    losses = spatial_losses(d, model)  # the eigen, deflection and combined losses (Eq. 27)
    gains = next((gain_records(t, d, model) for t in d.terms if isinstance(t, GainsTerm)), ())
    worst = max(gains, key=lambda g: abs(g["error_pct"]), default=None)
    if worst is not None and abs(worst["error_pct"]) > EXPORT_WARN_PCT:
        notes.append(f"modal gains: worst {worst['error_pct']:+.3g} % ({worst['kind']} mode at "
                     f"{worst['omega_truth_rad_s']:.6g} rad/s, {worst['point']})")
    factors = np.exp(x[n:])
    chosen = "nearest the finite-segment springs among the exact starts" if loss <= \
        EXACT_MATCH_PCT else "the lowest loss (no start matched every mode)"
    return FitResult(
        beam_name=beam.name, beam_fingerprint=beam.fingerprint(), joints=n,
        frequencies=int(sel.omega_truth_rad_s.size), stiffness=o.stiffness.value,
        lengths_m=model.lengths_m, stiffness_Nm_per_rad=model.stiffness_Nm_per_rad,
        stiffness_per_pose_Nm_per_rad=model.stiffness_Nm_per_rad[None, :], factors=factors,
        scf_mean=float(np.mean(factors)), scf_deviation_pct=np.zeros(1),
        poses_rad=np.zeros((1, nk)), omega_truth_rad_s=sel.omega_truth_rad_s,
        omega_model_rad_s=w[None, :], eigen_errors_pct=np.array([losses["eigen_loss_pct"]]),
        **losses, displacement_loss_pct=math.nan,
        tip_position_truth_m=target.tip_position_m,
        tip_displacement_truth_m=target.tip_displacement_m, tip_force_N=target.tip_force_N,
        mac=None, truth_source=target.source, truth_request=target.truth_request,
        static_theory_gap_pct=math.nan, squared=False, xi=o.xi_rad, eps=o.eps_rad,
        seed=o.seed, starts=o.starts, starts_run=len(runs), nfev=d.nfev,
        start_losses_pct=np.array([r[0] for r in sorted(runs, key=lambda r: r[2])]),
        wall_time_s=wall_s, success=success,
        message=message or f"{chosen}: start {index} of {len(runs)}: {solver_message}",
        warnings=tuple(notes), eigen_norm="relative", min_fraction=o.min_fraction,
        omega_errors_pct=errors[None, :], worst_mode_error_pct=float(np.max(np.abs(errors))),
        export_pose_rad=np.zeros(nk),
        stiffness_pose=f"{o.stiffness.value}: pose-independent springs of every axis "
        f"({o.axes.value}), "
        "fitted at the straight pose",
        omega_export_rad_s=w, omega_export_errors_pct=errors,
        worst_export_error_pct=float(np.max(np.abs(errors))), options=o,
        axes=o.axes.value, modes=records, gains=gains,
    )

